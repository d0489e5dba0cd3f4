#include "shellflow/geometry/shell_band.hpp"

namespace shellflow::geometry {

ShellBand::ShellBand(const grid::UniformGrid& grid) : m_grid(grid) {
  for (const grid::Location location : grid::kAllLocations) {
    m_flags[static_cast<int>(location)].assign(m_grid.size(location), 0);
  }
}

void ShellBand::clear() {
  for (int l = 0; l < grid::kLocationCount; ++l) {
    for (const std::int64_t index : m_samples[l]) m_flags[l][index] = 0;
    m_samples[l].clear();
  }
}

void ShellBand::add(const TriangleMesh& mesh, double margin) {
  mesh.boxes(m_scratch);
  add_boxes(m_scratch, margin);
}

void ShellBand::add_swept(const TriangleMesh& start, const TriangleMesh& end, double margin) {
  start.swept_boxes(end, m_scratch);
  add_boxes(m_scratch, margin);
}

void ShellBand::add_boxes(std::span<const Aabb> boxes, double margin) {
  // The five locations own disjoint arrays: one thread per location, no atomics.
  const int box_count = static_cast<int>(boxes.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (int l = 0; l < grid::kLocationCount; ++l) {
    const grid::Location location = grid::kAllLocations[l];
    const Eigen::Vector3i n = m_grid.counts(location);
    const std::int64_t sx = 1;
    const std::int64_t sy = n.x();
    const std::int64_t sz = std::int64_t{n.x()} * n.y();
    std::uint8_t* flags = m_flags[l].data();
    std::vector<std::int64_t>& samples = m_samples[l];
    for (int t = 0; t < box_count; ++t) {
      const Aabb box = boxes[t].inflated(margin);
      const grid::IndexBox range = m_grid.samples_in_box(location, box.lower, box.upper);
      if (range.empty()) continue;
      for (int k = range.lo.z(); k <= range.hi.z(); ++k) {
        for (int j = range.lo.y(); j <= range.hi.y(); ++j) {
          std::int64_t index = range.lo.x() * sx + j * sy + k * sz;
          for (int i = range.lo.x(); i <= range.hi.x(); ++i, ++index) {
            if (flags[index] == 0) {
              flags[index] = 1;
              samples.push_back(index);
            }
          }
        }
      }
    }
  }
}

}  // namespace shellflow::geometry
