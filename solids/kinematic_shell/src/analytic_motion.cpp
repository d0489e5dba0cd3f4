#include "shellflow/kinematic_shell/analytic_motion.hpp"

#include <Eigen/Geometry>

namespace shellflow::kinematic_shell {

AnalyticMotion::AnalyticMotion(const Eigen::Vector3d& velocity,
                               const Eigen::Vector3d& angular_velocity,
                               const Eigen::Vector3d& center)
    : m_velocity(velocity), m_angular_velocity(angular_velocity), m_center(center) {}

void AnalyticMotion::evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                              sdk::Positions& velocities) const {
  const double speed = m_angular_velocity.norm();
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (speed > 0) r = Eigen::AngleAxisd(speed * t, m_angular_velocity / speed).toRotationMatrix();
  const Eigen::Vector3d center = m_center + m_velocity * t;
  positions.resize(rest.rows(), 3);
  velocities.resize(rest.rows(), 3);
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const Eigen::Vector3d arm = r * (rest.row(i).transpose() - m_center);
    positions.row(i) = (center + arm).transpose();
    velocities.row(i) = (m_velocity + m_angular_velocity.cross(arm)).transpose();
  }
}

}  // namespace shellflow::kinematic_shell
