#pragma once
// Whether a shape that a scene gives the fluid (an emitter, a body of water, a probe) can
// ever reach the simulated box. A scene whose water or smoke lies wholly outside ran to the
// end without it and said nothing, so these inputs are refused (issue #50), all with the
// one message that outside_domain() writes.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

/// The box the grid spans, [origin, upper]: the domain as moved to fit cubic cells.
Eigen::AlignedBox3d domain_box(const grid::UniformGrid& grid);

/// Does `box` share a volume with the domain? One that only touches a face shares none: it
/// holds no part of a cell, so it can put no water or smoke into the grid.
bool overlaps_domain(const grid::UniformGrid& grid, const Eigen::AlignedBox3d& box);
/// Does the ball share a volume with the domain (the ball itself, not its bounding box)?
bool overlaps_domain(const grid::UniformGrid& grid, const Eigen::Vector3d& center, double radius);
/// Does the closed segment [a, b] meet the closed domain, its faces included?
bool meets_domain(const grid::UniformGrid& grid, const Eigen::Vector3d& a,
                  const Eigen::Vector3d& b);

/// "[(x, y, z), (x, y, z)]": a box's two corners, for messages.
std::string box_text(const Eigen::AlignedBox3d& box);

/// The error for the input at `json_path` that never reaches the domain: "<shape> lies
/// entirely outside the domain [...], so <consequence>: <fix>". `shape` names the input and
/// its extent ("the sphere emitter, bounds [...]").
ConfigError outside_domain(const grid::UniformGrid& grid, const std::string& json_path,
                           const std::string& shape, const std::string& consequence,
                           const std::string& fix);

/// The fix of a shape that adds or removes water or smoke: it must share a volume.
inline constexpr const char* kMoveInsideDomain =
    "move it (or the domain) so that the two share a volume (touching a face is not enough), "
    "or remove it";

}  // namespace shellflow::grid_fluid
