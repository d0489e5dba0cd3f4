#include "shellflow/grid_fluid/mac/domain_boundary.hpp"

#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::grid_fluid {

sdk::Schema DomainBoundary::schema() {
  using sdk::Schema;
  const auto side =
      Schema::variant("type", "condition on one face of the domain box (§4.3)")
          .option("wall", Schema::object("solid free-slip wall: normal velocity 0 (Neumann)"))
          .option("open", Schema::object("outflow: pressure 0 outside the face (Dirichlet)"))
          .option("inflow",
                  Schema::object("given velocity on the face (Neumann)")
                      .field("velocity", Schema::vec3(0.0, 0.0, 0.0)
                                             .unit("m/s")
                                             .doc("velocity imposed on the face; its normal "
                                                  "component must point into the domain")))
          .default_value({{"type", "wall"}});
  auto boundary = Schema::object("domain box faces; each left out is a wall");
  for (const char* name : kSideNames) boundary.field(name, side);
  return boundary;
}

DomainBoundary::DomainBoundary(const nlohmann::json& spec, const std::string& json_path) {
  for (int s = 0; s < 6; ++s) {
    const std::string name = kSideNames[s];
    if (!spec.contains(name)) continue;
    const auto& j = spec.at(name);
    const std::string type = j.value("type", std::string("wall"));
    FaceCondition& c = m_sides[s];
    if (type == "wall") {
      c.type = BoundaryType::Wall;
    } else if (type == "open") {
      c.type = BoundaryType::Open;
    } else if (type == "inflow") {
      c.type = BoundaryType::Inflow;
      if (j.contains("velocity")) c.velocity = sdk::json_vec3(j, "velocity");
      const int axis = s / 2;
      const double inward = (s % 2 == 0) ? c.velocity[axis] : -c.velocity[axis];
      if (inward < 0.0)
        throw ConfigError(json_path + "/" + name + "/velocity",
                          "an inflow velocity must point into the domain (flip the sign of "
                          "its normal component, or use \"open\" for an outflow)");
    } else {
      throw ConfigError(json_path + "/" + name + "/type",
                        "unknown boundary \"" + type + "\"; use wall, open or inflow");
    }
  }
}

bool DomainBoundary::has_open_side() const {
  for (const auto& s : m_sides)
    if (s.type == BoundaryType::Open) return true;
  return false;
}

}  // namespace shellflow::grid_fluid
