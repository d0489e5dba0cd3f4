#include "mass_spring_cloth/mass_spring_cloth.hpp"

#include <cmath>

#include "mass_spring_cloth/node_selection.hpp"
#include "shellflow/geometry/mesh_checks.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::cloth {

namespace {

using sdk::Schema;

template <class T>
T value_or(const nlohmann::json& object, const char* key, T fallback) {
  return object.contains(key) ? object.at(key).get<T>() : fallback;
}

sdk::Schema collider_schema() {
  return Schema::variant("type", "analytic static collider")
      .option(
          "plane",
          Schema::object("half-space below a plane")
              .field("point", Schema::vec3(0, 0, 0).unit("m"))
              .field("normal", Schema::vec3(0, 1, 0).doc("points to the side the cloth stays on")))
      .option("sphere", Schema::object("solid sphere")
                            .field("center", Schema::vec3().unit("m"))
                            .field("radius", Schema::number().min(0.0, false).unit("m")))
      .option("box", Schema::object("solid axis-aligned box")
                         .field("min", Schema::vec3().unit("m"))
                         .field("max", Schema::vec3().unit("m")));
}

}  // namespace

sdk::Schema MassSpringCloth::schema() {
  const ClothMaterial m;
  const SolverSettings s;
  const CollisionSettings c;
  return Schema::object(
             "Implicit mass-spring cloth (Baraff-Witkin 1998 backward Euler; structural and shear "
             "springs, quadratic bending of Bergou et al. 2006; Bridson et al. 2002 collisions).")
      .field("mesh", geometry::mesh_schema())
      .field("transform", geometry::transform_schema().optional())
      .field("surface_density",
             Schema::number(m.surface_density)
                 .min(0.0, false)
                 .unit("kg/m^2")
                 .doc("mass per area; lumped, a third of each triangle per node"))
      .field("stretch_stiffness", Schema::number(m.stretch_stiffness)
                                      .min(0.0)
                                      .unit("N/m")
                                      .doc("membrane stiffness: force per width per unit strain"))
      .field("stretch_damping",
             Schema::number(m.stretch_damping)
                 .min(0.0)
                 .unit("N s/m")
                 .doc("membrane viscosity: force per width per unit strain rate"))
      .field("shear_stiffness", Schema::number(m.shear_stiffness)
                                    .min(0.0)
                                    .unit("N/m")
                                    .doc("modulus of the cross-edge (shear) springs"))
      .field("shear_damping", Schema::number(m.shear_damping).min(0.0).unit("N s/m"))
      .field("bending_stiffness", Schema::number(m.bending_stiffness)
                                      .min(0.0)
                                      .unit("N m")
                                      .doc("bending rigidity (flat rest shape)"))
      .field("bending_damping", Schema::number(m.bending_damping).min(0.0).unit("N m s"))
      .field("air_damping", Schema::number(m.air_damping)
                                .min(0.0)
                                .unit("kg/(m^2 s)")
                                .doc("drag per area and velocity, on every node"))
      .field("receives_fluid_forces", Schema::boolean(true).doc("two-way coupled (§5.1)"))
      .field(
          "solver",
          Schema::object("time integration")
              .field("linear_solver", Schema::string("cg")
                                          .one_of({"cg", "cholmod"})
                                          .doc("CG with a two-level (block Jacobi + aggregation) "
                                               "preconditioner, or CHOLMOD Cholesky"))
              .field("cg_tolerance",
                     Schema::number(s.cg_tolerance).min(0.0, false).doc("relative residual"))
              .field("cg_max_iterations", Schema::integer(s.cg_max_iterations).min(1))
              .field("substeps",
                     Schema::integer(s.min_substeps).min(1).doc("substeps per advance, at least"))
              .field("max_substep",
                     Schema::number(s.max_substep).min(0.0, false).unit("s").doc("longest substep"))
              .field("max_strain", Schema::number(s.max_strain)
                                       .min(0.0)
                                       .doc("strain limit of the structural springs (Provot 1995); "
                                            "0 switches it off")))
      .field(
          "collision",
          Schema::object("contact")
              .field("thickness",
                     Schema::number(0.0).min(0.0).unit("m").doc(
                         "proximity distance; 0 means a quarter of the mean edge length"))
              .field("friction", Schema::number(c.friction).min(0.0))
              .field("self_collision", Schema::boolean(c.self_collision))
              .field("ccd_iterations", Schema::integer(c.ccd_iterations)
                                           .min(1)
                                           .doc("continuous-collision passes before impact zones")))
      .field("colliders", Schema::array(collider_schema()).optional())
      .field("pins", node_selection_schema("nodes held in place").optional())
      .field("attachments",
             Schema::array(
                 Schema::object("nodes moved along a piecewise-linear path")
                     .field("nodes", node_selection_schema("the attached nodes"))
                     .field("times", Schema::number_list().unit("s"))
                     .field("translations", Schema::array(Schema::vec3())
                                                .unit("m")
                                                .doc("offset from the rest position at each time")))
                 .optional());
}

MassSpringCloth::MassSpringCloth(const nlohmann::json& params, const sdk::Context& context) {
  if (!params.contains("mesh")) throw ConfigError("/mesh", "the cloth needs a \"mesh\"");
  auto mesh = geometry::make_mesh(params.at("mesh"));
  if (params.contains("transform"))
    geometry::apply_transform(geometry::transform_from_json(params.at("transform")), mesh);
  // Cloth refuses every mesh defect. A zero-area triangle has no rest shape: spring
  // stiffnesses divide by rest lengths and bending weights are cotangents of its angles. A
  // vertex no triangle uses is dropped, which renumbers the nodes after it, and "pins" and
  // "attachments" select nodes by index. An edge of three or more triangles has no bending
  // stencil (Bergou et al. 2006 pair the two triangles of an edge) and no inside/outside for
  // self-collision.
  using Severity = geometry::MeshCheckSeverity;
  geometry::check_mesh(mesh, {Severity::Error, Severity::Error, Severity::Error}, "/mesh",
                       context.instance_name);
  std::optional<GridShape> grid;
  if (params.at("mesh").value("type", "") == "grid") {
    // Missing counts take the mesh schema's defaults, as make_mesh does.
    const auto& mesh_spec = params.at("mesh");
    const auto& fields = geometry::mesh_schema().json().at("options").at("grid").at("fields");
    const auto count = [&](const char* key) {
      return mesh_spec.contains(key) ? mesh_spec.at(key).get<int>()
                                     : fields.at(key).at("default").get<int>();
    };
    grid = GridShape{count("nodes_u"), count("nodes_v")};
  }

  ClothMaterial m;
  m.surface_density = value_or(params, "surface_density", m.surface_density);
  m.stretch_stiffness = value_or(params, "stretch_stiffness", m.stretch_stiffness);
  m.stretch_damping = value_or(params, "stretch_damping", m.stretch_damping);
  m.shear_stiffness = value_or(params, "shear_stiffness", m.shear_stiffness);
  m.shear_damping = value_or(params, "shear_damping", m.shear_damping);
  m.bending_stiffness = value_or(params, "bending_stiffness", m.bending_stiffness);
  m.bending_damping = value_or(params, "bending_damping", m.bending_damping);
  m.air_damping = value_or(params, "air_damping", m.air_damping);

  SolverSettings s;
  const auto solver = params.value("solver", nlohmann::json::object());
  const std::string kind = value_or<std::string>(solver, "linear_solver", "cg");
  if (kind != "cg" && kind != "cholmod")
    throw ConfigError("/solver/linear_solver", "use \"cg\" or \"cholmod\"");
  s.linear_solver = kind == "cg" ? LinearSolverKind::ConjugateGradient : LinearSolverKind::Cholmod;
  s.cg_tolerance = value_or(solver, "cg_tolerance", s.cg_tolerance);
  s.cg_max_iterations = value_or(solver, "cg_max_iterations", s.cg_max_iterations);
  s.min_substeps = value_or(solver, "substeps", s.min_substeps);
  s.max_substep = value_or(solver, "max_substep", s.max_substep);
  s.max_strain = value_or(solver, "max_strain", s.max_strain);

  ClothModel model = build_cloth_model(mesh.positions, mesh.triangles, m);
  CollisionSettings c;
  const auto collision = params.value("collision", nlohmann::json::object());
  c.thickness = value_or(collision, "thickness", 0.0);
  if (c.thickness <= 0.0) {
    double total = 0.0;
    for (int e = 0; e < model.structural_count; ++e) total += model.springs[e].rest_length;
    c.thickness = 0.25 * total / std::max(1, model.structural_count);
  }
  c.friction = value_or(collision, "friction", c.friction);
  c.self_collision = value_or(collision, "self_collision", c.self_collision);
  c.ccd_iterations = value_or(collision, "ccd_iterations", c.ccd_iterations);

  m_simulator = std::make_unique<ClothSimulator>(std::move(model), s, c, context.gravity);

  if (params.contains("colliders")) {
    const auto& list = params.at("colliders");
    for (size_t k = 0; k < list.size(); ++k) {
      const auto& item = list[k];
      const std::string type = item.value("type", "");
      if (type == "plane") {
        m_simulator->add_collider(
            AnalyticCollider::plane(sdk::json_vec3(item, "point"), sdk::json_vec3(item, "normal")));
      } else if (type == "sphere") {
        m_simulator->add_collider(AnalyticCollider::sphere(sdk::json_vec3(item, "center"),
                                                           item.at("radius").get<double>()));
      } else if (type == "box") {
        m_simulator->add_collider(
            AnalyticCollider::box(sdk::json_vec3(item, "min"), sdk::json_vec3(item, "max")));
      } else {
        throw ConfigError("/colliders/" + std::to_string(k) + "/type",
                          "unknown collider \"" + type + "\"; use plane, sphere or box");
      }
    }
  }
  if (params.contains("pins"))
    for (int k : select_nodes(params.at("pins"), mesh.positions, grid, "/pins"))
      m_simulator->pin(k);
  if (params.contains("attachments")) {
    const auto& list = params.at("attachments");
    for (size_t a = 0; a < list.size(); ++a) {
      const std::string path = "/attachments/" + std::to_string(a);
      const auto& item = list[a];
      const auto times = item.at("times").get<std::vector<double>>();
      std::vector<Eigen::Vector3d> translations;
      for (const auto& t : item.at("translations")) translations.push_back(sdk::json_vec3(t));
      if (times.empty() || times.size() != translations.size())
        throw ConfigError(path, "give one translation per time, at least one");
      if (!std::is_sorted(times.begin(), times.end()))
        throw ConfigError(path + "/times", "key times must increase");
      const KinematicPath kinematic(times, translations);
      for (int k : select_nodes(item.at("nodes"), mesh.positions, grid, path + "/nodes"))
        m_simulator->attach(k, kinematic);
    }
  }

  m_surface.name = context.instance_name + "/cloth";
  m_surface.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  m_surface.surface_density = Eigen::VectorXd::Constant(mesh.triangles.rows(), m.surface_density);
  m_surface.receives_fluid_forces = value_or(params, "receives_fluid_forces", true);
  update_surface();
}

void MassSpringCloth::update_surface() {
  const int n = m_simulator->node_count();
  m_surface.positions = Eigen::Map<const sdk::Positions>(m_simulator->positions().data(), n, 3);
  m_surface.velocities = Eigen::Map<const sdk::Positions>(m_simulator->velocities().data(), n, 3);
}

void MassSpringCloth::set_colliders(sdk::ShellSet colliders) {
  m_colliders.assign(colliders.begin(), colliders.end());
}

void MassSpringCloth::advance(double t, double dt,
                              std::span<const sdk::TriangleVectors> triangle_forces) {
  const int n = m_simulator->node_count();
  Eigen::VectorXd external;
  if (m_surface.receives_fluid_forces && !triangle_forces.empty() &&
      triangle_forces[0].rows() > 0) {
    const auto& forces = triangle_forces[0];
    const auto& tris = *m_surface.triangles;
    if (forces.rows() != tris.rows())
      throw Error("mass_spring_cloth: got " + std::to_string(forces.rows()) +
                  " triangle forces for " + std::to_string(tris.rows()) + " triangles");
    external = Eigen::VectorXd::Zero(3 * n);
    for (int t = 0; t < tris.rows(); ++t)
      for (int k = 0; k < 3; ++k)  // a third of each triangle's force to each node
        external.segment<3>(3 * tris(t, k)) += forces.row(t).transpose() / 3.0;
  }
  m_simulator->set_external_forces(std::move(external));
  m_simulator->set_obstacles(m_colliders, t);
  m_simulator->advance(t, dt);
  update_surface();
}

void MassSpringCloth::save(sdk::StateWriter& out) const {
  m_simulator->save(out);
}

void MassSpringCloth::restore(sdk::StateReader& in) {
  m_simulator->restore(in);
  update_surface();
}

void MassSpringCloth::report(sdk::Metrics& out) const {
  const auto& s = m_simulator->statistics();
  out.set("kinetic_energy", m_simulator->kinetic_energy());
  out.set("potential_energy", m_simulator->potential_energy());
  out.set("cg_iterations", s.cg_iterations);
  out.set("substeps", s.substeps);
  out.set("collider_contacts", s.collider_contacts);
  out.set("self_proximity_contacts", s.collisions.proximity_contacts);
  out.set("ccd_collisions", s.collisions.ccd_collisions);
  out.set("impact_zones", s.collisions.impact_zones);
  out.set("max_strain", m_simulator->max_structural_strain());
  // The centre of mass, for known answers from metrics.csv alone (free fall: a parabola).
  const Eigen::VectorXd& m = m_simulator->model().masses;
  const Eigen::VectorXd& x = m_simulator->positions();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int k = 0; k < m.size(); ++k) centre += m[k] * x.segment<3>(3 * k);
  centre /= m.sum();
  out.set("center_x", centre.x());
  out.set("center_y", centre.y());
  out.set("center_z", centre.z());
}

}  // namespace shellflow::cloth
