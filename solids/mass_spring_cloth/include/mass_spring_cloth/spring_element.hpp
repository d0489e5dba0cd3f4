#pragma once
// Force and force Jacobians of one damped linear spring (Baraff–Witkin 1998 §4.1):
//   f_i = -k (L - L0) u - c (u . (v_i - v_j)) u,  u = (x_i - x_j) / L,  f_j = -f_i,
//   df_i/dx_i = -k [u u^T + (1 - L0/L)(I - u u^T)],  df_i/dv_i = -c u u^T,
// and the (i,j), (j,i), (j,j) blocks are -, -, + the (i,i) block. The damping force's
// position derivative is left out of the solve, as in Baraff–Witkin.

#include <Eigen/Core>
#include <algorithm>

#include "mass_spring_cloth/cloth_model.hpp"

namespace shellflow::cloth {

struct SpringEvaluation {
  Eigen::Vector3d force_i = Eigen::Vector3d::Zero();  ///< force on node i (node j gets -force_i)
  Eigen::Matrix3d dfdx = Eigen::Matrix3d::Zero();     ///< df_i/dx_i
  Eigen::Matrix3d dfdv = Eigen::Matrix3d::Zero();     ///< df_i/dv_i
};

/// `exact`: keep the (1 - L0/L) term when compressed (indefinite); otherwise clamp it at
/// zero so the system matrix stays positive definite (Choi and Ko 2002).
inline SpringEvaluation evaluate_spring(const Spring& s, const Eigen::Vector3d& xi,
                                        const Eigen::Vector3d& xj, const Eigen::Vector3d& vi,
                                        const Eigen::Vector3d& vj, bool exact) {
  SpringEvaluation out;
  const Eigen::Vector3d d = xi - xj;
  const double L = d.norm();
  if (!(L > 0.0)) return out;
  const Eigen::Vector3d u = d / L;
  const Eigen::Matrix3d uu = u * u.transpose();
  const double stretch_rate = u.dot(vi - vj);
  out.force_i = -(s.stiffness * (L - s.rest_length) + s.damping * stretch_rate) * u;
  double transverse = 1.0 - s.rest_length / L;
  if (!exact) transverse = std::max(transverse, 0.0);
  out.dfdx = -s.stiffness * (uu + transverse * (Eigen::Matrix3d::Identity() - uu));
  out.dfdv = -s.damping * uu;
  return out;
}

inline double spring_energy(const Spring& s, const Eigen::Vector3d& xi, const Eigen::Vector3d& xj) {
  const double stretch = (xi - xj).norm() - s.rest_length;
  return 0.5 * s.stiffness * stretch * stretch;
}

}  // namespace shellflow::cloth
