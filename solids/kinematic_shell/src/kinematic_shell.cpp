#include "shellflow/kinematic_shell/kinematic_shell.hpp"

#include <algorithm>
#include <cmath>

#include "shellflow/geometry/mesh_checks.hpp"
#include "shellflow/geometry/mesh_edges.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::kinematic_shell {

sdk::Schema KinematicShell::schema() {
  using sdk::Schema;
  return Schema::object(
             "a thin shell moved by a script (keyframes, analytic motion or a deforming wave); it "
             "pushes the fluid but feels no fluid force")
      .field("mesh", geometry::mesh_schema())
      .field("transform", geometry::transform_schema())
      .field("surface_density", Schema::number(1.0)
                                    .min(0.0, false)
                                    .unit("kg/m^2")
                                    .doc("mass per unit area (for the fluid coupling and metrics)"))
      .field("motion", motion_schema().optional());
}

KinematicShell::KinematicShell(const nlohmann::json& params, const sdk::Context& context) {
  auto mesh = geometry::make_mesh(params.at("mesh"), "/mesh");
  geometry::apply_transform(geometry::transform_from_json(
                                params.value("transform", nlohmann::json::object()), "/transform"),
                            mesh);
  // A scripted shell copes with every mesh defect, so each is a warning with its count:
  // the script moves nodes without a rest shape or edge topology; a zero-area triangle
  // carries no mass and no fluid force (both scale with area); no parameter addresses a
  // node by index, so dropped vertices change nothing. (A solid that collides with this
  // shell sees its triangles as they are.)
  using Severity = geometry::MeshCheckSeverity;
  geometry::check_mesh(mesh, {Severity::Warning, Severity::Warning, Severity::Warning}, "/mesh",
                       context.instance_name);
  m_rest = mesh.positions;
  m_motion = make_motion(params.value("motion", nlohmann::json()), "/motion");
  const double density = params.value("surface_density", 1.0);
  if (!(density > 0)) throw ConfigError("/surface_density", "must be positive");

  auto& surface = m_surface[0];
  surface.name = context.instance_name.empty() ? "kinematic_shell" : context.instance_name;
  surface.triangles = std::make_shared<const sdk::Triangles>(std::move(mesh.triangles));
  surface.surface_density = Eigen::VectorXd::Constant(surface.triangles->rows(), density);
  surface.receives_fluid_forces = false;

  // Lumped masses: a third of each triangle's area × density to each corner.
  m_node_mass.setZero(m_rest.rows());
  const auto& triangles = *surface.triangles;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::Vector3d a = m_rest.row(triangles(t, 0));
    const Eigen::Vector3d b = m_rest.row(triangles(t, 1));
    const Eigen::Vector3d c = m_rest.row(triangles(t, 2));
    const double third = density * 0.5 * (b - a).cross(c - a).norm() / 3.0;
    for (int k = 0; k < 3; ++k) m_node_mass[triangles(t, k)] += third;
  }
  // Each edge once, for the strain figure (a rigid motion keeps every length).
  m_edges = geometry::MeshEdges(triangles).edges;
  m_rest_length.resize(static_cast<Eigen::Index>(m_edges.size()));
  for (size_t e = 0; e < m_edges.size(); ++e)
    m_rest_length[static_cast<Eigen::Index>(e)] =
        (m_rest.row(m_edges[e][1]) - m_rest.row(m_edges[e][0])).norm();
  m_time = 0.0;
  update();
}

void KinematicShell::update() {
  m_motion->evaluate(m_time, m_rest, m_surface[0].positions, m_surface[0].velocities);
}

void KinematicShell::advance(double t, double dt,
                             std::span<const sdk::TriangleVectors> /*triangle_forces*/) {
  // Kinematic: the script alone decides the state at t + dt (fluid forces are ignored).
  m_time = t + dt;
  update();
}

void KinematicShell::save(sdk::StateWriter& out) const {
  out.write(m_time);
  out.write_matrix(m_surface[0].positions);
  out.write_matrix(m_surface[0].velocities);
}

void KinematicShell::restore(sdk::StateReader& in) {
  m_time = in.read<double>();
  in.read_matrix(m_surface[0].positions);
  in.read_matrix(m_surface[0].velocities);
  if (m_surface[0].positions.rows() != m_rest.rows())
    throw Error("kinematic_shell '" + m_surface[0].name +
                "': restore() got a state with a different node count");
}

void KinematicShell::report(sdk::Metrics& out) const {
  const auto& x = m_surface[0].positions;
  out.set("kinetic_energy", 0.5 * m_node_mass.dot(m_surface[0].velocities.rowwise().squaredNorm()));
  const Eigen::Vector3d center = x.colwise().mean();
  out.set("center_x", center.x());
  out.set("center_y", center.y());
  out.set("center_z", center.z());
  double strain = 0.0;
  for (size_t e = 0; e < m_edges.size(); ++e) {
    const double rest = m_rest_length[static_cast<Eigen::Index>(e)];
    if (rest > 0.0)  // a zero-length edge (a warned-of defect) has no strain to speak of
      strain = std::max(
          strain, std::abs((x.row(m_edges[e][1]) - x.row(m_edges[e][0])).norm() - rest) / rest);
  }
  out.set("max_edge_strain", strain);
}

}  // namespace shellflow::kinematic_shell
