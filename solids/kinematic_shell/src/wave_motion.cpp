#include "shellflow/kinematic_shell/wave_motion.hpp"

#include <cmath>
#include <stdexcept>

namespace shellflow::kinematic_shell {

WaveMotion::WaveMotion(const WaveParameters& parameters) : m_parameters(parameters) {
  if (!(parameters.direction.norm() > 0.0))
    throw std::invalid_argument("wave motion: the direction must not be zero");
  if (!(parameters.amplitude >= 0.0))
    throw std::invalid_argument("wave motion: the amplitude must be >= 0");
  m_direction = parameters.direction.normalized();
}

double WaveMotion::displacement(const Eigen::Vector3d& x0, double t) const {
  const auto& p = m_parameters;
  return p.amplitude * std::sin(p.wave_vector.dot(x0) - p.angular_frequency * t + p.phase);
}

void WaveMotion::evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                          sdk::Positions& velocities) const {
  const auto& p = m_parameters;
  positions.resize(rest.rows(), 3);
  velocities.resize(rest.rows(), 3);
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const Eigen::Vector3d x0 = rest.row(i).transpose();
    const double phase = p.wave_vector.dot(x0) - p.angular_frequency * t + p.phase;
    positions.row(i) = (x0 + p.amplitude * std::sin(phase) * m_direction).transpose();
    velocities.row(i) =
        (-p.amplitude * p.angular_frequency * std::cos(phase) * m_direction).transpose();
  }
}

}  // namespace shellflow::kinematic_shell
