#pragma once
// Selecting cloth nodes in the scene file, for pins and kinematic attachments:
//   {"indices": [0, 5], "grid": ["top_left", "top_right"], "box_min": [..], "box_max": [..]}
// The selection is the union of the given parts. "grid" names an edge ("top", "bottom",
// "left", "right") or a corner ("top_left", ...) of a generated grid (node (i, j) has index
// i + nodes_u * j, j = nodes_v - 1 is the top edge); the box is in world coordinates.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::cloth {

struct GridShape {
  int nodes_u = 0;
  int nodes_v = 0;
};

sdk::Schema node_selection_schema(const std::string& doc);

/// Indices selected by `selector` (sorted, unique). Throws ConfigError with `json_path`
/// when a part cannot apply (grid names without a grid mesh, bad index, empty selection).
std::vector<int> select_nodes(const nlohmann::json& selector, const sdk::Positions& positions,
                              const std::optional<GridShape>& grid, const std::string& json_path);

}  // namespace shellflow::cloth
