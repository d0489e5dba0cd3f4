#include "falling_plate.hpp"

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::template_solid {

sdk::Schema FallingPlate::schema() {
  using sdk::Schema;
  return Schema::object("A rigid thin plate falling under gravity, pushed by the fluid (template).")
      .field("width", Schema::number(1.0).min(0.0, false).unit("m").doc("edge length along x"))
      .field("height", Schema::number(1.0).min(0.0, false).unit("m").doc("edge length along y"))
      .field("nodes",
             Schema::integer(11).min(2).max(1000).doc("nodes per edge of the triangle grid"))
      .field("surface_density",
             Schema::number(1.0).min(0.0, false).unit("kg/m^2").doc("mass per area"))
      .field("transform", geometry::transform_schema().doc("placement of the plate at t = 0"))
      .field("velocity", Schema::vec3(0, 0, 0).unit("m/s").doc("initial velocity of the centre"))
      .field("angular_velocity",
             Schema::vec3(0, 0, 0).unit("rad/s").doc("initial angular velocity"));
}

FallingPlate::FallingPlate(const nlohmann::json& params, const sdk::Context& context)
    : m_gravity(context.gravity) {
  const double a = params["width"], b = params["height"];
  const int n = params["nodes"];
  const auto placement = geometry::transform_from_json(params["transform"]);
  if (!placement.linear().isUnitary(1e-9))
    throw ConfigError("/transform/scale",
                      "a rigid plate cannot be scaled: set its width and height instead");
  const auto mesh = geometry::make_grid(a, b, n, n, geometry::GridPattern::Alternating);

  const double sigma = params["surface_density"];
  m_mass = sigma * a * b;
  m_body_inertia = (m_mass / 12.0) * Eigen::Vector3d(b * b, a * a, a * a + b * b).asDiagonal();
  m_center = placement.translation();
  m_orientation = Eigen::Quaterniond(placement.linear());
  m_velocity = sdk::json_vec3(params, "velocity");
  m_angular_velocity = sdk::json_vec3(params, "angular_velocity");
  m_body_positions = mesh.positions;  // the grid is centred on the origin

  m_surface.name = context.instance_name;
  m_surface.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  m_surface.surface_density = Eigen::VectorXd::Constant(mesh.triangles.rows(), sigma);
  m_surface.receives_fluid_forces = true;
  update_surface();
}

void FallingPlate::update_surface() {
  const Eigen::Matrix3d R = m_orientation.toRotationMatrix();
  m_surface.positions = (m_body_positions * R.transpose()).rowwise() + m_center.transpose();
  m_surface.velocities.resize(m_surface.positions.rows(), 3);
  for (int i = 0; i < m_surface.positions.rows(); ++i) {
    const Eigen::Vector3d r = m_surface.positions.row(i).transpose() - m_center;
    m_surface.velocities.row(i) = (m_velocity + m_angular_velocity.cross(r)).transpose();
  }
}

void FallingPlate::advance(double /*t*/, double dt, std::span<const sdk::TriangleVectors> forces) {
  // §5.1: each triangle's force acts at its barycentre.
  Eigen::Vector3d force = m_mass * m_gravity;
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  if (!forces.empty() && forces[0].rows() > 0) {
    const auto& tris = *m_surface.triangles;
    for (int t = 0; t < tris.rows(); ++t) {
      const Eigen::Vector3d f = forces[0].row(t).transpose();
      const Eigen::Vector3d barycentre =
          (m_surface.positions.row(tris(t, 0)) + m_surface.positions.row(tris(t, 1)) +
           m_surface.positions.row(tris(t, 2)))
              .transpose() /
          3.0;
      force += f;
      torque += (barycentre - m_center).cross(f);
    }
  }
  // Translation: exact for a force constant over the step.
  const Eigen::Vector3d acceleration = force / m_mass;
  m_center += m_velocity * dt + 0.5 * acceleration * dt * dt;
  m_velocity += acceleration * dt;

  // Rotation: Euler's equations in the world frame, then rotate by ω dt.
  const Eigen::Matrix3d R = m_orientation.toRotationMatrix();
  const Eigen::Matrix3d inertia = R * m_body_inertia * R.transpose();
  const Eigen::Vector3d gyroscopic = m_angular_velocity.cross(inertia * m_angular_velocity);
  m_angular_velocity += inertia.ldlt().solve(torque - gyroscopic) * dt;
  const double angle = m_angular_velocity.norm() * dt;
  if (angle > 0.0)
    m_orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, m_angular_velocity.normalized())) *
                    m_orientation;
  m_orientation.normalize();
  update_surface();
}

void FallingPlate::save(sdk::StateWriter& out) const {
  out.write_matrix(m_center);
  out.write_matrix(Eigen::Vector4d(m_orientation.coeffs()));
  out.write_matrix(m_velocity);
  out.write_matrix(m_angular_velocity);
}

void FallingPlate::restore(sdk::StateReader& in) {
  Eigen::Vector4d q;
  in.read_matrix(m_center);
  in.read_matrix(q);
  in.read_matrix(m_velocity);
  in.read_matrix(m_angular_velocity);
  m_orientation.coeffs() = q;
  update_surface();
}

void FallingPlate::report(sdk::Metrics& out) const {
  const Eigen::Matrix3d R = m_orientation.toRotationMatrix();
  const double rotational =
      0.5 * m_angular_velocity.dot(R * m_body_inertia * R.transpose() * m_angular_velocity);
  out.set("kinetic_energy", 0.5 * m_mass * m_velocity.squaredNorm() + rotational);
  out.set("height", m_center.dot(-m_gravity.normalized()));
  // Linear momentum m v: what the fluid's coupling impulses add up to (bench's momentum_balance).
  out.set("momentum_x", m_mass * m_velocity.x());
  out.set("momentum_y", m_mass * m_velocity.y());
  out.set("momentum_z", m_mass * m_velocity.z());
}

}  // namespace shellflow::template_solid

SHELLFLOW_SOLID_PLUGIN(shellflow::template_solid::FallingPlate, "template_solid")
