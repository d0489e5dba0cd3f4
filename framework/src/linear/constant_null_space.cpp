#include "shellflow/linear/constant_null_space.hpp"

namespace shellflow::linear {

ConstantNullSpace::ConstantNullSpace(std::vector<int> group, int groups)
    : m_group(std::move(group)), m_inverse_count(groups, 0.0), m_groups(groups) {
  for (const int g : m_group)
    if (g >= 0) m_inverse_count[g] += 1.0;
  for (auto& c : m_inverse_count) c = c > 0.0 ? 1.0 / c : 0.0;
}

void ConstantNullSpace::project(Eigen::VectorXd& v) const {
  if (m_groups == 0) return;
  // Sequential: the group sums are a scatter, and this is one cheap pass next to a V-cycle.
  std::vector<double> mean(m_groups, 0.0);
  const int n = static_cast<int>(m_group.size());
  for (int i = 0; i < n; ++i)
    if (m_group[i] >= 0) mean[m_group[i]] += v[i];
  for (int g = 0; g < m_groups; ++g) mean[g] *= m_inverse_count[g];
  for (int i = 0; i < n; ++i)
    if (m_group[i] >= 0) v[i] -= mean[m_group[i]];
}

}  // namespace shellflow::linear
