#pragma once
// ConstantNullSpace: groups of unknowns on each of which the constant vector is in the
// null space of A — the enclosed fluid regions of the §4.3 projection (Guendelman et al.
// 2005), whose pressure is fixed only up to a constant. CG on such a consistent
// semidefinite system stays in the range of A if the preconditioned residual is kept
// orthogonal to these constants (project() removes each group's mean).

#include <Eigen/Core>
#include <vector>

namespace shellflow::linear {

class ConstantNullSpace {
 public:
  ConstantNullSpace() = default;
  /// `group[i]` in [0, groups) names the singular group of unknown i, or -1 for none.
  ConstantNullSpace(std::vector<int> group, int groups);

  bool empty() const { return m_groups == 0; }
  /// v −= (mean of v over its group) on every group.
  void project(Eigen::VectorXd& v) const;

 private:
  std::vector<int> m_group;
  std::vector<double> m_inverse_count;
  int m_groups = 0;
};

}  // namespace shellflow::linear
