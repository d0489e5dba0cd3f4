#pragma once
// SweptPointInvalidator: §3 invalidation over grid samples. A sample is invalid when a
// triangle moving linearly from x^n to x^{n+1} passes through it, or when it lies inside
// a wedge at the start or the end of the step (point_invalidated). Only the samples in
// each triangle's swept box (grown by ε/2) are tested: cost scales with shell area.

#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/triangle_mesh.hpp"
#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::geometry {

class SweptPointInvalidator {
 public:
  /// `epsilon`: wedge thickness ε; `tolerance`: the swept test's distance tolerance
  /// (defaults to 1e-3 ε: above position round-off, well below ε).
  SweptPointInvalidator(const grid::UniformGrid& grid, double epsilon, double tolerance = -1.0);

  double epsilon() const { return m_epsilon; }
  double tolerance() const { return m_tolerance; }

  /// Sets invalid[i] = 1 for every sample i of `location` invalidated by the motion
  /// start → end (same topology) and appends the newly set indices to `newly_invalid`.
  /// Samples already flagged are skipped. Returns the number newly set.
  std::int64_t invalidate(grid::Location location, const TriangleMesh& start,
                          const TriangleMesh& end, std::span<std::uint8_t> invalid,
                          std::vector<std::int64_t>& newly_invalid) const;

 private:
  grid::UniformGrid m_grid;
  double m_epsilon;
  double m_tolerance;
};

}  // namespace shellflow::geometry
