#pragma once
// Constant linear and angular velocity: x(t) = c + v t + R(ω t)(x0 − c), where R(ω t)
// rotates by |ω| t about ω/|ω| and c is the world point the rotation is about at t = 0
// (it moves with v). Exact velocity: ẋ = v + ω × R(ω t)(x0 − c).

#include <Eigen/Core>

#include "shellflow/kinematic_shell/motion.hpp"

namespace shellflow::kinematic_shell {

class AnalyticMotion final : public Motion {
 public:
  AnalyticMotion(const Eigen::Vector3d& velocity, const Eigen::Vector3d& angular_velocity,
                 const Eigen::Vector3d& center);

  void evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                sdk::Positions& velocities) const override;

 private:
  Eigen::Vector3d m_velocity;
  Eigen::Vector3d m_angular_velocity;
  Eigen::Vector3d m_center;
};

}  // namespace shellflow::kinematic_shell
