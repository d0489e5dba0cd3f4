#include "shellflow/grid_fluid/mac/domain_overlap.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <utility>

namespace shellflow::grid_fluid {

Eigen::AlignedBox3d domain_box(const grid::UniformGrid& grid) {
  return Eigen::AlignedBox3d(grid.origin(), grid.upper());
}

bool overlaps_domain(const grid::UniformGrid& grid, const Eigen::AlignedBox3d& box) {
  const Eigen::AlignedBox3d domain = domain_box(grid);
  // Strict: equal coordinates are a shared face, of no volume.
  return (box.min().array() < domain.max().array()).all() &&
         (box.max().array() > domain.min().array()).all();
}

bool overlaps_domain(const grid::UniformGrid& grid, const Eigen::Vector3d& center, double radius) {
  // Strict: a ball at exactly its radius from the domain touches it at one point.
  return domain_box(grid).squaredExteriorDistance(center) < radius * radius;
}

bool meets_domain(const grid::UniformGrid& grid, const Eigen::Vector3d& a,
                  const Eigen::Vector3d& b) {
  // Clips the parameter range [0, 1] of a + t (b − a) to each slab (Liang–Barsky).
  const Eigen::AlignedBox3d domain = domain_box(grid);
  double t0 = 0.0, t1 = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double d = b[axis] - a[axis];
    const double lo = domain.min()[axis], hi = domain.max()[axis];
    if (d == 0.0) {
      if (a[axis] < lo || a[axis] > hi) return false;
      continue;
    }
    double enter = (lo - a[axis]) / d, leave = (hi - a[axis]) / d;
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
    if (t0 > t1) return false;
  }
  return true;
}

std::string box_text(const Eigen::AlignedBox3d& box) {
  // + 0: a computed −0 (a negated zero) prints as 0.
  const Eigen::Vector3d lo = box.min().array() + 0.0;
  const Eigen::Vector3d hi = box.max().array() + 0.0;
  return fmt::format("[({:g}, {:g}, {:g}), ({:g}, {:g}, {:g})]", lo.x(), lo.y(), lo.z(), hi.x(),
                     hi.y(), hi.z());
}

ConfigError outside_domain(const grid::UniformGrid& grid, const std::string& json_path,
                           const std::string& shape, const std::string& consequence,
                           const std::string& fix) {
  return ConfigError(json_path, shape + " lies entirely outside the domain " +
                                    box_text(domain_box(grid)) + ", so " + consequence + ": " +
                                    fix);
}

}  // namespace shellflow::grid_fluid
