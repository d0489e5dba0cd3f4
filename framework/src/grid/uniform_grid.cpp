#include "shellflow/grid/uniform_grid.hpp"

#include <algorithm>
#include <cmath>

#include "shellflow/sdk/error.hpp"

namespace shellflow::grid {

UniformGrid::UniformGrid(const Eigen::Vector3d& origin, double dx, const Eigen::Vector3i& cells)
    : m_origin(origin), m_dx(dx), m_cells(cells) {
  if (!(dx > 0.0) || (cells.array() < 1).any()) {
    throw Error("UniformGrid: dx must be > 0 and every cell count >= 1");
  }
}

Eigen::Vector3d UniformGrid::stagger(Location location) {
  switch (location) {
    case Location::Node:
      return {0.0, 0.0, 0.0};
    case Location::Cell:
      return {0.5, 0.5, 0.5};
    case Location::FaceX:
      return {0.0, 0.5, 0.5};
    case Location::FaceY:
      return {0.5, 0.0, 0.5};
    case Location::FaceZ:
      return {0.5, 0.5, 0.0};
  }
  return {0.0, 0.0, 0.0};
}

IndexBox UniformGrid::samples_in_box(Location location, const Eigen::Vector3d& lower,
                                     const Eigen::Vector3d& upper) const {
  const Eigen::Vector3d offset = stagger(location);
  const Eigen::Vector3i n = counts(location);
  IndexBox box;
  for (int a = 0; a < 3; ++a) {
    // Sample s lies at origin + (s + offset) dx; keep those with lower <= x <= upper.
    const double lo = std::ceil((lower[a] - m_origin[a]) / m_dx - offset[a]);
    const double hi = std::floor((upper[a] - m_origin[a]) / m_dx - offset[a]);
    // Clamp in double before converting, so far-away boxes cannot overflow an int.
    box.lo[a] = static_cast<int>(std::clamp(lo, 0.0, static_cast<double>(n[a])));
    box.hi[a] = static_cast<int>(std::clamp(hi, -1.0, static_cast<double>(n[a] - 1)));
  }
  return box;
}

}  // namespace shellflow::grid
