#pragma once
// Broad phase for cloth contact: axis-aligned boxes hashed into a uniform grid of cells
// (Teschner et al. 2003, "Optimized Spatial Hashing for Collision Detection of Deformable
// Objects"). Entries are (cell key, box) pairs sorted by key; a query visits the cells of
// its box and returns the boxes that overlap it, each once.

#include <Eigen/Geometry>
#include <cstdint>
#include <utility>
#include <vector>

namespace shellflow::cloth {

class SpatialHash {
 public:
  using Box = Eigen::AlignedBox3d;

  void build(std::vector<Box> boxes, double cell_size);
  /// Indices of the stored boxes overlapping `box`, increasing, into `out` (cleared first).
  void query(const Box& box, std::vector<int>& out) const;
  const Box& box(int k) const { return m_boxes[k]; }

 private:
  std::uint64_t key(long ix, long iy, long iz) const;
  double m_inverse_cell = 1.0;
  std::vector<Box> m_boxes;
  std::vector<std::pair<std::uint64_t, int>> m_entries;  ///< sorted by key
  std::vector<int> m_oversized;  ///< boxes spanning too many cells, returned by every query
};

}  // namespace shellflow::cloth
