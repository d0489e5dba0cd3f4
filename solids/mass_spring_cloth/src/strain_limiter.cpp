#include "mass_spring_cloth/strain_limiter.hpp"

#include <algorithm>

namespace shellflow::cloth {

StrainLimitStatistics limit_strain(const ClothModel& model, const Eigen::VectorXd& x,
                                   Eigen::VectorXd& v, const std::vector<double>& inverse_mass,
                                   const std::vector<Eigen::Vector3d>& contact_normal, double h,
                                   double max_strain, int max_sweeps) {
  StrainLimitStatistics stats;
  // Most steps stretch no spring past the limit: find that out in parallel first.
  const double squared_limit = (1.0 + max_strain) * (1.0 + max_strain);
  bool any = false;
#pragma omp parallel for schedule(static) reduction(|| : any) if (model.structural_count > 16384)
  for (int e = 0; e < model.structural_count; ++e) {
    const auto& s = model.springs[e];
    const Eigen::Vector3d d = (x.segment<3>(3 * s.i) + h * v.segment<3>(3 * s.i)) -
                              (x.segment<3>(3 * s.j) + h * v.segment<3>(3 * s.j));
    any = any || d.squaredNorm() > squared_limit * s.rest_length * s.rest_length;
  }
  if (!any) return stats;
  const auto change = [&](int k, const Eigen::Vector3d& dv) {
    const Eigen::Vector3d& n = contact_normal[k];
    const double into = dv.dot(n);
    v.segment<3>(3 * k) += into < 0.0 ? Eigen::Vector3d(dv - into * n) : dv;
  };
  // A spring whose nodes no correction moved since it was last checked is still within
  // the limit: after the first sweep only springs at moved nodes are looked at.
  const int n = static_cast<int>(inverse_mass.size());
  std::vector<char> moved(n, 1), moving(n, 0);
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    ++stats.sweeps;
    int corrected = 0;
    for (int e = 0; e < model.structural_count; ++e) {
      const auto& s = model.springs[e];
      if (!moved[s.i] && !moved[s.j] && !moving[s.i] && !moving[s.j]) continue;
      const double wi = inverse_mass[s.i], wj = inverse_mass[s.j];
      if (wi + wj == 0.0) continue;
      const Eigen::Vector3d d = (x.segment<3>(3 * s.i) + h * v.segment<3>(3 * s.i)) -
                                (x.segment<3>(3 * s.j) + h * v.segment<3>(3 * s.j));
      const double length = d.norm(), limit = (1.0 + max_strain) * s.rest_length;
      if (length <= limit) continue;
      // Shorten to the limit along the spring; the excess shared by inverse mass.
      const Eigen::Vector3d excess = ((length - limit) / (length * (wi + wj) * h)) * d;
      change(s.i, -wi * excess);
      change(s.j, wj * excess);
      moving[s.i] = moving[s.j] = 1;
      ++corrected;
    }
    moved.swap(moving);
    std::fill(moving.begin(), moving.end(), 0);
    stats.corrections += corrected;
    if (corrected == 0) break;
  }
  return stats;
}

}  // namespace shellflow::cloth
