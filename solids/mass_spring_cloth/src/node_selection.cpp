#include "mass_spring_cloth/node_selection.hpp"

#include <algorithm>

#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::cloth {

sdk::Schema node_selection_schema(const std::string& doc) {
  return sdk::Schema::object(doc)
      .field("indices", sdk::Schema::integer_list().optional().doc("node indices"))
      .field("grid", sdk::Schema::array(
                         sdk::Schema::string().one_of({"top", "bottom", "left", "right", "top_left",
                                                       "top_right", "bottom_left", "bottom_right"}))
                         .optional()
                         .doc("named edges and corners of a generated grid mesh"))
      .field("box_min",
             sdk::Schema::vec3().optional().unit("m").doc("with box_max: nodes inside this box"))
      .field("box_max", sdk::Schema::vec3().optional().unit("m"));
}

std::vector<int> select_nodes(const nlohmann::json& selector, const sdk::Positions& positions,
                              const std::optional<GridShape>& grid, const std::string& json_path) {
  const int n = static_cast<int>(positions.rows());
  std::vector<int> out;
  if (selector.contains("indices")) {
    for (const auto& item : selector.at("indices")) {
      const int k = item.get<int>();
      if (k < 0 || k >= n)
        throw ConfigError(json_path + "/indices", "node " + std::to_string(k) +
                                                      " does not exist; the cloth has " +
                                                      std::to_string(n) + " nodes");
      out.push_back(k);
    }
  }
  if (selector.contains("grid")) {
    if (!grid)
      throw ConfigError(json_path + "/grid",
                        "named edges and corners need a \"grid\" mesh; use \"indices\" or a box");
    const int nu = grid->nodes_u, nv = grid->nodes_v;
    for (const auto& item : selector.at("grid")) {
      const std::string name = item.get<std::string>();
      const auto index = [&](int i, int j) { return i + nu * j; };
      if (name == "top" || name == "bottom") {
        const int j = name == "top" ? nv - 1 : 0;
        for (int i = 0; i < nu; ++i) out.push_back(index(i, j));
      } else if (name == "left" || name == "right") {
        const int i = name == "left" ? 0 : nu - 1;
        for (int j = 0; j < nv; ++j) out.push_back(index(i, j));
      } else if (name == "top_left") {
        out.push_back(index(0, nv - 1));
      } else if (name == "top_right") {
        out.push_back(index(nu - 1, nv - 1));
      } else if (name == "bottom_left") {
        out.push_back(index(0, 0));
      } else if (name == "bottom_right") {
        out.push_back(index(nu - 1, 0));
      } else {
        throw ConfigError(json_path + "/grid", "unknown grid part \"" + name +
                                                   "\"; use top, bottom, left, right or a corner "
                                                   "such as top_left");
      }
    }
  }
  if (selector.contains("box_min") != selector.contains("box_max"))
    throw ConfigError(json_path, "give both box_min and box_max");
  if (selector.contains("box_min")) {
    const Eigen::Vector3d lo = sdk::json_vec3(selector, "box_min"),
                          hi = sdk::json_vec3(selector, "box_max");
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d x = positions.row(k).transpose();
      if ((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()) out.push_back(k);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (out.empty())
    throw ConfigError(json_path, "selects no node; check the indices, grid names or box");
  return out;
}

}  // namespace shellflow::cloth
