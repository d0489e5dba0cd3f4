#include "shellflow/grid_fluid/mac/node_fields.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::grid_fluid {

NodeFields::NodeFields(const grid::UniformGrid& grid, double ambient_temperature, bool smoke) {
  const std::int64_t n = grid.size(grid::Location::Node);
  for (auto& v : m_velocity) v.assign(n, 0.0);
  if (!smoke) return;
  m_density.assign(n, 0.0);
  m_temperature.assign(n, ambient_temperature);
}

NodeStencil node_stencil(const grid::UniformGrid& grid, const Eigen::Vector3d& p) {
  NodeStencil s;
  const Eigen::Vector3d q = (p - grid.origin()) / grid.dx();
  for (int a = 0; a < 3; ++a) {
    const int cells = grid.cells()[a];
    const double x = std::clamp(q[a], 0.0, static_cast<double>(cells));
    const int i = std::min(static_cast<int>(std::floor(x)), cells - 1);
    s.base[a] = i;
    s.fraction[a] = x - i;
  }
  return s;
}

}  // namespace shellflow::grid_fluid
