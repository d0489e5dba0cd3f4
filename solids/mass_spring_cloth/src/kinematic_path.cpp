#include "mass_spring_cloth/kinematic_path.hpp"

#include <algorithm>

#include "shellflow/sdk/error.hpp"

namespace shellflow::cloth {

KinematicPath::KinematicPath(std::vector<double> times, std::vector<Eigen::Vector3d> translations)
    : m_times(std::move(times)), m_translations(std::move(translations)) {
  if (m_times.empty() || m_times.size() != m_translations.size())
    throw Error("kinematic path: give as many times as translations, at least one");
  if (!std::is_sorted(m_times.begin(), m_times.end()))
    throw Error("kinematic path: key times must increase");
}

Eigen::Vector3d KinematicPath::translation(double t) const {
  if (m_times.empty()) return Eigen::Vector3d::Zero();
  if (t <= m_times.front()) return m_translations.front();
  if (t >= m_times.back()) return m_translations.back();
  const auto it = std::upper_bound(m_times.begin(), m_times.end(), t);
  const size_t k = static_cast<size_t>(it - m_times.begin());
  const double t0 = m_times[k - 1], t1 = m_times[k];
  const double s = t1 > t0 ? (t - t0) / (t1 - t0) : 1.0;
  return (1.0 - s) * m_translations[k - 1] + s * m_translations[k];
}

}  // namespace shellflow::cloth
