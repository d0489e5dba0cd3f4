#include "shellflow/bullet_rigid/bullet_rigid_solver.hpp"

#include <set>
#include <string>

#include "shellflow/bullet_rigid/fluid_wrench.hpp"
#include "shellflow/geometry/mesh_checks.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::bullet_rigid {

namespace {

sdk::Schema body_schema() {
  using sdk::Schema;
  return Schema::object("One rigid thin shell; its mass and inertia come from the shell itself.")
      .field("name", Schema::string().doc("unique within this solver; the surface is "
                                          "\"<instance>/<name>\""))
      .field("mesh", geometry::mesh_schema())
      .field("transform", geometry::transform_schema().optional())
      .field(
          "surface_density",
          Schema::number(1.0).min(0.0, false).unit("kg/m^2").doc("mass per unit area of the shell"))
      .field("motion", Schema::string("dynamic")
                           .one_of({"dynamic", "kinematic"})
                           .doc("dynamic: moved by gravity, contacts and the fluid; "
                                "kinematic: moves at the given constant velocities"))
      .field("velocity", Schema::vec3(0.0, 0.0, 0.0)
                             .unit("m/s")
                             .doc("initial (dynamic) or constant (kinematic) velocity of the "
                                  "centre of mass"))
      .field("angular_velocity", Schema::vec3(0.0, 0.0, 0.0)
                                     .unit("rad/s")
                                     .doc("initial (dynamic) or constant (kinematic) angular "
                                          "velocity about the centre of mass"))
      .field("friction", Schema::number(0.9).min(0.0).doc(
                             "Coulomb friction coefficient; Bullet uses the product of the two "
                             "bodies' coefficients"))
      .field("restitution", Schema::number(0.2).min(0.0).max(1.0).doc(
                                "coefficient of restitution; Bullet uses the product of the two "
                                "bodies' coefficients"));
}

sdk::Schema ground_schema() {
  using sdk::Schema;
  return Schema::object("A static plane {x : normal · x = height} under the bodies.")
      .field("height", Schema::number(0.0).unit("m").doc("offset of the plane along its normal"))
      .field("normal", Schema::vec3(0.0, 1.0, 0.0).doc("pointing into the world; normalised"))
      .field("friction", Schema::number(1.0).min(0.0).doc(
                             "multiplies each body's friction (1: the body's own applies)"))
      .field("restitution", Schema::number(1.0).min(0.0).max(1.0).doc(
                                "multiplies each body's restitution (1: the body's own applies)"));
}

}  // namespace

sdk::Schema BulletRigidSolver::schema() {
  using sdk::Schema;
  return Schema::object(
             "Dynamic and kinematic rigid thin shells through Bullet (double precision). Mass "
             "and inertia from the shell (surface density × area), contact on the triangle "
             "meshes (GImpact), fluid forces summed into a force and torque per body (§5.1).")
      .field("bodies", Schema::array(body_schema()).min_items(1).doc("the rigid shells"))
      .field("ground", ground_schema().optional())
      .field("substep", Schema::number(1.0 / 240.0)
                            .min(0.0, false)
                            .unit("s")
                            .doc("longest internal Bullet step: advance(dt) takes ceil(dt/substep) "
                                 "equal steps"))
      .field("margin", Schema::number(0.005)
                           .min(0.0, false)
                           .unit("m")
                           .doc("collision skin of every shell: contacts start at this distance"))
      .field("solver_iterations",
             Schema::integer(10).min(1).doc("sequential-impulse contact iterations per substep"));
}

RigidWorldSettings settings_from_json(const nlohmann::json& params, const sdk::Context& context) {
  RigidWorldSettings s;
  s.gravity = context.gravity;
  s.max_substep = params.value("substep", 1.0 / 240.0);
  s.margin = params.value("margin", 0.005);
  s.solver_iterations = params.value("solver_iterations", 10);
  if (params.contains("ground") && !params.at("ground").is_null()) {
    const auto& g = params.at("ground");
    GroundPlane ground;
    ground.height = g.value("height", 0.0);
    if (g.contains("normal")) ground.normal = sdk::json_vec3(g, "normal");
    if (!(ground.normal.norm() > 0.0))
      throw ConfigError("/ground/normal",
                        "the ground normal is the zero vector; give the "
                        "direction pointing into the world, e.g. [0, 1, 0]");
    ground.normal.normalize();
    ground.friction = g.value("friction", 1.0);
    ground.restitution = g.value("restitution", 1.0);
    s.ground = ground;
  }
  return s;
}

std::vector<RigidShellSpec> bodies_from_json(const nlohmann::json& params) {
  std::vector<RigidShellSpec> bodies;
  std::set<std::string> names;
  const auto& list = params.at("bodies");
  for (size_t i = 0; i < list.size(); ++i) {
    const auto& j = list.at(i);
    const std::string path = "/bodies/" + std::to_string(i);
    RigidShellSpec b;
    b.name = j.at("name").get<std::string>();
    if (b.name.empty() || b.name.find('/') != std::string::npos)
      throw ConfigError(path + "/name", "body name '" + b.name +
                                            "' must be non-empty and hold no '/' (the surface "
                                            "is called \"<instance>/<name>\")");
    if (!names.insert(b.name).second)
      throw ConfigError(path + "/name",
                        "two bodies are called '" + b.name + "'; give each a unique name");
    b.mesh = geometry::make_mesh(j.at("mesh"), path + "/mesh");
    if (j.contains("transform"))
      geometry::apply_transform(
          geometry::transform_from_json(j.at("transform"), path + "/transform"), b.mesh);
    // A rigid shell needs no edge topology: mass properties sum over triangles and Bullet's
    // GImpact collides triangle by triangle, so an edge of three or more triangles and
    // dropped vertices (no parameter addresses a node) are warnings. A zero-area triangle
    // is an error: GImpact normalises each triangle's normal for its contact plane
    // (btPrimitiveTriangle::buildTriPlane), which is NaN for zero area.
    using Severity = geometry::MeshCheckSeverity;
    geometry::check_mesh(b.mesh, {Severity::Error, Severity::Warning, Severity::Warning},
                         path + "/mesh", "body '" + b.name + "'");
    b.surface_density = j.value("surface_density", 1.0);
    b.motion = j.value("motion", std::string("dynamic")) == "kinematic" ? Motion::Kinematic
                                                                        : Motion::Dynamic;
    if (j.contains("velocity")) b.velocity = sdk::json_vec3(j, "velocity");
    if (j.contains("angular_velocity")) b.angular_velocity = sdk::json_vec3(j, "angular_velocity");
    b.friction = j.value("friction", 0.9);
    b.restitution = j.value("restitution", 0.2);
    bodies.push_back(std::move(b));
  }
  return bodies;
}

BulletRigidSolver::BulletRigidSolver(const nlohmann::json& params, const sdk::Context& context) {
  auto bodies = bodies_from_json(params);
  try {
    m_world =
        std::make_unique<RigidShellWorld>(settings_from_json(params, context), std::move(bodies));
  } catch (const ConfigError&) {
    throw;
  } catch (const Error& e) {
    throw ConfigError("", e.what());
  }
  for (int i = 0; i < m_world->body_count(); ++i) {
    const RigidShellSpec& spec = m_world->spec(i);
    sdk::ShellSurface s;
    s.name = context.instance_name + "/" + spec.name;
    s.triangles = std::make_shared<const sdk::Triangles>(spec.mesh.triangles);
    s.surface_density = Eigen::VectorXd::Constant(spec.mesh.triangles.rows(), spec.surface_density);
    s.receives_fluid_forces = spec.motion == Motion::Dynamic;
    m_surfaces.push_back(std::move(s));
  }
  update_surfaces();
}

BulletRigidSolver::~BulletRigidSolver() = default;

std::span<const sdk::ShellSurface> BulletRigidSolver::surfaces() const {
  return m_surfaces;
}

void BulletRigidSolver::update_surfaces() {
  for (int i = 0; i < m_world->body_count(); ++i) {
    auto& s = m_surfaces[static_cast<size_t>(i)];
    m_world->node_positions(i, s.positions);
    m_world->node_velocities(i, s.velocities);
    if (!s.receives_fluid_forces) continue;
    // The fluid moves the body as one in its coupling solve (sdk::RigidBody).
    sdk::RigidBody body;
    body.centre_of_mass = m_world->state(i).centre_of_mass;
    body.inverse_mass = Eigen::Matrix3d::Identity() / m_world->mass_properties(i).mass;
    body.inverse_inertia = m_world->world_inverse_inertia(i);
    body.acceleration = m_world->gravity();
    s.rigid = body;
  }
}

void BulletRigidSolver::set_colliders(sdk::ShellSet colliders) {
  m_world->set_colliders(colliders);
}

void BulletRigidSolver::advance(double t, double dt,
                                std::span<const sdk::TriangleVectors> triangle_forces) {
  if (!triangle_forces.empty() && triangle_forces.size() != m_surfaces.size())
    throw Error("bullet_rigid advance(): " + std::to_string(triangle_forces.size()) +
                " force arrays for " + std::to_string(m_surfaces.size()) +
                " surfaces; give one per surface, in surfaces() order");
  std::vector<Wrench> wrenches;
  if (!triangle_forces.empty()) {
    wrenches.resize(m_surfaces.size());
    for (size_t i = 0; i < m_surfaces.size(); ++i) {
      const auto& s = m_surfaces[i];
      if (!s.receives_fluid_forces) continue;
      wrenches[i] = sum_triangle_forces(s.positions, *s.triangles, triangle_forces[i],
                                        m_world->state(static_cast<int>(i)).centre_of_mass);
    }
  }
  m_world->advance(t, dt, wrenches);
  update_surfaces();
}

void BulletRigidSolver::save(sdk::StateWriter& out) const {
  m_world->save(out);
}

void BulletRigidSolver::restore(sdk::StateReader& in) {
  m_world->restore(in);
  update_surfaces();
}

void BulletRigidSolver::report(sdk::Metrics& out) const {
  out.set("kinetic_energy", m_world->kinetic_energy());
  out.set("potential_energy", m_world->potential_energy());
  out.set("contacts", m_world->contact_count());
  out.set("substeps", m_world->last_substeps());
  // Each body's pose, for known answers (a free fall, the draft of a floating hull): its
  // centre of mass and its lowest node's height along −gravity (+y without gravity).
  const Eigen::Vector3d& g = m_world->gravity();
  const Eigen::Vector3d up = g.norm() > 0.0 ? Eigen::Vector3d(-g.normalized()) : Eigen::Vector3d::UnitY();
  for (int i = 0; i < m_world->body_count(); ++i) {
    const std::string body = m_world->spec(i).name + ".";
    const Eigen::Vector3d c = m_world->state(i).centre_of_mass;
    out.set(body + "center_x", c.x());
    out.set(body + "center_y", c.y());
    out.set(body + "center_z", c.z());
    out.set(body + "lowest", (m_surfaces[static_cast<size_t>(i)].positions * up).minCoeff());
  }
}

}  // namespace shellflow::bullet_rigid
