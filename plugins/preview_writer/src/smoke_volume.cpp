#include "shellflow/preview_writer/smoke_volume.hpp"

#include <algorithm>

namespace shellflow::preview_writer {

SmokeVolume::SmokeVolume(const sdk::FieldView& field) : m_field(field, "density") {}

double SmokeVolume::density(const Eigen::Vector3d& x) const {
  return m_field.contains(x) ? m_field.value(x) : 0.0;
}

bool SmokeVolume::clip(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                       double& s_in, double& s_out) const {
  return m_field.clip(origin, direction, s_in, s_out);
}

double SmokeVolume::optical_depth(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                  double s0, double s1, double h, double max_depth) const {
  double s_in = 0.0;
  double s_out = 0.0;
  if (!clip(origin, direction, s_in, s_out)) return 0.0;
  const double begin = std::max(s0, s_in);
  const double end = std::min(s1, s_out);
  double depth = 0.0;
  // Steps start at the box entry so that, along an axis, step ends fall on sample
  // planes whenever h divides the spacing (then the midpoint rule is exact).
  for (long n = 0; depth <= max_depth; ++n) {
    const double s = begin + static_cast<double>(n) * h;  // no drift from repeated sums
    if (!(s < end)) break;
    const double length = std::min(h, end - s);
    depth += density(origin + (s + 0.5 * length) * direction) * length;  // midpoint rule
  }
  return depth;
}

}  // namespace shellflow::preview_writer
