#pragma once
// ShellBand: the grid samples near the shells (§3: "for each triangle, a slightly
// enlarged bounding box is used to label all the voxels ... in close proximity to the
// surface thus possibly requiring special treatment"). Labelling visits, per triangle,
// only the samples inside its enlarged box, so it costs O(shell area / dx^2 × box
// volume), never a sweep of the whole grid; clear() resets only what was labelled.
// For every location (nodes, cells, three face families) it keeps a byte flag per
// sample (the dense lookup) and the sparse list of labelled flat indices (the loop).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/triangle_mesh.hpp"
#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::geometry {

class ShellBand {
 public:
  /// Allocates one zeroed flag array per location (the only full-grid pass).
  explicit ShellBand(const grid::UniformGrid& grid);

  /// Unlabels every labelled sample (cost proportional to the band).
  void clear();
  /// Labels every sample within each triangle's box grown by `margin` on every side.
  void add(const TriangleMesh& mesh, double margin);
  /// Labels every sample within each triangle's box over the linear motion
  /// start → end (union of both end boxes), grown by `margin`.
  void add_swept(const TriangleMesh& start, const TriangleMesh& end, double margin);
  /// Labels samples in each given box grown by `margin` (the shared kernel).
  void add_boxes(std::span<const Aabb> boxes, double margin);

  const grid::UniformGrid& grid() const { return m_grid; }
  bool contains(grid::Location location, std::int64_t index) const {
    return m_flags[static_cast<int>(location)][index] != 0;
  }
  /// Flat indices (UniformGrid::index) of the labelled samples, in labelling order.
  std::span<const std::int64_t> samples(grid::Location location) const {
    return m_samples[static_cast<int>(location)];
  }
  /// One byte per sample: 1 in the band, 0 outside.
  std::span<const std::uint8_t> flags(grid::Location location) const {
    return m_flags[static_cast<int>(location)];
  }

 private:
  grid::UniformGrid m_grid;
  std::array<std::vector<std::uint8_t>, grid::kLocationCount> m_flags;
  std::array<std::vector<std::int64_t>, grid::kLocationCount> m_samples;
  std::vector<Aabb> m_scratch;
};

}  // namespace shellflow::geometry
