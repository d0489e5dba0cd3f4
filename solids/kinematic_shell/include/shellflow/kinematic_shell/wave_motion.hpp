#pragma once
// A travelling wave deforming the shell: every node moves along a fixed direction d by
//   x(t) = x0 + A sin(k · x0 − ω t + φ) d,   ẋ(t) = −A ω cos(k · x0 − ω t + φ) d,
// with x0 its placed rest position, A the amplitude, k the wave vector, ω the angular
// frequency and φ the phase. For a flat sheet with d its normal and k in its plane this
// is the "wavy deforming sheet" of the sealed leak test (Guendelman et al. 2005, §3–4:
// shells that deform, not only move rigidly, must not let smoke through). Velocities are
// exact (the time derivative), not differences.

#include <Eigen/Core>

#include "shellflow/kinematic_shell/motion.hpp"

namespace shellflow::kinematic_shell {

struct WaveParameters {
  double amplitude = 0.0;                                 ///< A [m]
  Eigen::Vector3d wave_vector = Eigen::Vector3d::Zero();  ///< k [rad/m]
  double angular_frequency = 0.0;                         ///< ω [rad/s]
  double phase = 0.0;                                     ///< φ [rad]
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();   ///< d, normalised on use
};

class WaveMotion final : public Motion {
 public:
  /// std::invalid_argument for a zero direction or a negative amplitude.
  explicit WaveMotion(const WaveParameters& parameters);

  void evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                sdk::Positions& velocities) const override;

  /// The displacement A sin(k · x0 − ω t + φ) of rest point x0 at time t, along direction().
  double displacement(const Eigen::Vector3d& x0, double t) const;
  const Eigen::Vector3d& direction() const { return m_direction; }

 private:
  WaveParameters m_parameters;
  Eigen::Vector3d m_direction;
};

}  // namespace shellflow::kinematic_shell
