#include "shellflow/grid_fluid/mac/mac_grid.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::grid_fluid {

MacGrid::MacGrid(const grid::UniformGrid& grid) : m_grid(grid) {
  for (int a = 0; a < 3; ++a) m_face_velocity[a].assign(m_grid.size(face_location(a)), 0.0);
  m_pressure.assign(m_grid.size(grid::Location::Cell), 0.0);
}

double MacGrid::max_face_speed() const {
  double m = 0.0;
  for (int a = 0; a < 3; ++a) {
    const auto& u = m_face_velocity[a];
    const std::int64_t n = static_cast<std::int64_t>(u.size());
#pragma omp parallel for reduction(max : m)
    for (std::int64_t f = 0; f < n; ++f) m = std::max(m, std::abs(u[f]));
  }
  return m;
}

double MacGrid::outward_flux(const Eigen::Vector3i& cell) const {
  double flux = 0.0;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3i hi = cell;
    hi[a] += 1;
    const grid::Location loc = face_location(a);
    flux += m_face_velocity[a][m_grid.index(loc, hi)] - m_face_velocity[a][m_grid.index(loc, cell)];
  }
  return flux;
}

}  // namespace shellflow::grid_fluid
