#include "shellflow/grid_fluid/mac/node_fields.hpp"

namespace shellflow::grid_fluid {

NodeFields::NodeFields(const grid::UniformGrid& grid, double ambient_temperature, bool smoke,
                       bool temperature)
    : m_ambient(ambient_temperature) {
  const std::int64_t n = grid.size(grid::Location::Node);
  for (auto& v : m_velocity) v.assign(n, 0.0);
  if (!smoke) return;
  m_density.assign(n, 0.0);
  if (temperature) m_temperature.assign(n, ambient_temperature);
}

}  // namespace shellflow::grid_fluid
