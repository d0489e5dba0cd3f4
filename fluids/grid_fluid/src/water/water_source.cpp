#include "shellflow/grid_fluid/water/water_source.hpp"

namespace shellflow::grid_fluid {

std::int64_t WaterSource::apply(double t, LevelSet& level_set) const {
  if (!active(t)) return 0;
  const grid::UniformGrid& grid = level_set.grid();
  const grid::IndexBox box =
      m_emitter.bounding_samples(grid, grid::Location::Node, level_set.band());
  if (box.empty()) return 0;
  auto& phi = level_set.phi();
  std::int64_t inside = 0;
#pragma omp parallel for collapse(2) reduction(+ : inside)
  for (int k = box.lo.z(); k <= box.hi.z(); ++k)
    for (int j = box.lo.y(); j <= box.hi.y(); ++j)
      for (int i = box.lo.x(); i <= box.hi.x(); ++i) {
        const Eigen::Vector3i ijk(i, j, k);
        const double d = m_emitter.signed_distance(grid.position(grid::Location::Node, ijk));
        double& p = phi[grid.index(grid::Location::Node, ijk)];
        p = std::min(p, d);
        inside += d <= 0.0 ? 1 : 0;
      }
  return inside;
}

}  // namespace shellflow::grid_fluid
