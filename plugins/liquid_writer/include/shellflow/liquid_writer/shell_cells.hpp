#pragma once
// The cells of a node grid that thin shells touch: the cells a liquid mesh must not enter
// (see liquid_mesher.hpp). A cell is touched when a triangle meets the closed cell (faces
// included), by the exact separating-axis test; the cell is grown by 1e-9 Δx so that
// round-off never loses one the triangle just touches. Cost scales with shell area: only
// the cells whose centre lies in a triangle's box grown by half a cell diagonal are tested.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::liquid_writer {

/// A box of nodes: node (i,j,k) at origin + dx (i,j,k), dims nodes per axis; cell (i,j,k)
/// spans nodes i..i+1, j..j+1, k..k+1.
struct NodeBox {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double dx = 0.0;
  std::array<int, 3> dims{0, 0, 0};
};

/// The cells of `box` (lower-corner node index) touched by a triangle of `shells`, each
/// once, sorted.
std::vector<Eigen::Vector3i> cells_touched_by_shells(const NodeBox& box, sdk::ShellSet shells);

}  // namespace shellflow::liquid_writer
