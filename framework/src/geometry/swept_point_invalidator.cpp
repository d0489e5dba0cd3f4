#include "shellflow/geometry/swept_point_invalidator.hpp"

#include <omp.h>

#include "shellflow/geometry/swept_point.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::geometry {

SweptPointInvalidator::SweptPointInvalidator(const grid::UniformGrid& grid, double epsilon,
                                             double tolerance)
    : m_grid(grid), m_epsilon(epsilon), m_tolerance(tolerance > 0.0 ? tolerance : 1e-3 * epsilon) {
  if (!(epsilon > 0.0)) throw Error("SweptPointInvalidator: epsilon must be > 0");
}

std::int64_t SweptPointInvalidator::invalidate(grid::Location location, const TriangleMesh& start,
                                               const TriangleMesh& end,
                                               std::span<std::uint8_t> invalid,
                                               std::vector<std::int64_t>& newly_invalid) const {
  if (!start.same_topology(end)) {
    throw Error("SweptPointInvalidator: start and end meshes differ in topology");
  }
  if (static_cast<std::int64_t>(invalid.size()) != m_grid.size(location)) {
    throw Error("SweptPointInvalidator: flag array size does not match the grid location");
  }
  const int triangle_count = start.triangle_count();
  const double margin = 0.5 * m_epsilon + m_tolerance;
  const int threads = omp_get_max_threads();
  std::vector<std::vector<std::int64_t>> found(threads);
  // Phase 1 (parallel): `invalid` is only read; each thread collects its hits.
#pragma omp parallel
  {
    std::vector<std::int64_t>& mine = found[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 64)
    for (int t = 0; t < triangle_count; ++t) {
      const TriangleCorners c0 = start.corners(t);
      const TriangleCorners c1 = end.corners(t);
      Aabb box = start.box(t);
      box.extend(end.box(t));
      box = box.inflated(margin);
      const grid::IndexBox range = m_grid.samples_in_box(location, box.lower, box.upper);
      if (range.empty()) continue;
      for (int k = range.lo.z(); k <= range.hi.z(); ++k) {
        for (int j = range.lo.y(); j <= range.hi.y(); ++j) {
          for (int i = range.lo.x(); i <= range.hi.x(); ++i) {
            const std::int64_t index = m_grid.index(location, i, j, k);
            if (invalid[index] != 0) continue;
            const Eigen::Vector3d p = m_grid.position(location, Eigen::Vector3i(i, j, k));
            if (point_invalidated(p, c0, c1, m_epsilon, m_tolerance)) mine.push_back(index);
          }
        }
      }
    }
  }
  // Phase 2 (serial): set the flags, dropping duplicates found by neighbouring triangles.
  std::int64_t added = 0;
  for (const std::vector<std::int64_t>& list : found) {
    for (const std::int64_t index : list) {
      if (invalid[index] != 0) continue;
      invalid[index] = 1;
      newly_invalid.push_back(index);
      ++added;
    }
  }
  return added;
}

}  // namespace shellflow::geometry
