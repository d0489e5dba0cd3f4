#pragma once
// The water a scene starts with (§4.4): the union of pools (water below a height along
// the up direction), boxes, spheres and closed meshes (inside = water), written into a
// LevelSet as the minimum of their signed distances, in order; an entry with
// "subtract": true carves its inside out of the water before it (the maximum of φ and
// minus its distance: Zalesak's slot cut from his sphere). A mesh's sign comes from the parity
// of its crossings along each +x grid row (a row through an edge or a vertex crosses
// exactly one of the triangles about it; exact for a closed, consistently closed
// surface; an open mesh is refused by the caller's validation), its distance from the
// closest surface point, within the band only.
//
//   "initial": [{"type": "pool", "height": 0.4},
//               {"type": "box", "min": [0, 0, 0], "max": [0.2, 0.4, 1]},
//               {"type": "sphere", "center": [0.5, 0.8, 0.5], "radius": 0.1},
//               {"type": "mesh", "mesh": {"type": "obj", "file": "blob.obj"},
//                "transform": {"translate": [0, 0.2, 0]}},
//               {"type": "box", "min": [0.1, 0, 0], "max": [0.12, 0.1, 1], "subtract": true}]

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>

#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

/// The schema of one "initial" entry.
sdk::Schema initial_water_schema();

/// φ = min over `entries` (validated against initial_water_schema()) of their signed
/// distances (max(φ, −d) for a subtracted entry), clamped to ±band; `up` (unit) is the pools' up
/// direction. ConfigError at `json_path`/i/... for values the schema cannot check, and at
/// `json_path`/i for an entry that shares no volume with the level set's domain (outside_domain()).
void fill_initial_water(const nlohmann::json& entries, const Eigen::Vector3d& up,
                        const std::string& json_path, LevelSet& level_set);

}  // namespace shellflow::grid_fluid
