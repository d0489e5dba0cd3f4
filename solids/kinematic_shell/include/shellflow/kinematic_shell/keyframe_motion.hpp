#pragma once
// Keyframed rigid poses. Each key is a pose P_k(x) = R_k x + T_k applied after the
// initial placement; between keys k and k+1 (s = (t − t_k)/(t_{k+1} − t_k)):
//  - Slerp: x(t) = R(s) x0 + (1−s) T_k + s T_{k+1}, R(s) = R_k · exp(s θ a) where
//    θ a is the rotation vector of R_k^{-1} R_{k+1} taken the shorter way (Shoemake 1985);
//    the motion is rigid and ẋ = ω × R(s) x0 + (T_{k+1} − T_k)/Δt with ω = R_k θ a / Δt.
//  - Linear: x(t) = (1−s) P_k(x0) + s P_{k+1}(x0), each node on a straight line.
// Before the first key and from the last key on the pose holds with zero velocity
// (as PhysBAM's keyframed rigid bodies do). At an interior key time the velocity is the
// one of the segment that starts there.

#include <Eigen/Geometry>
#include <vector>

#include "shellflow/kinematic_shell/motion.hpp"

namespace shellflow::kinematic_shell {

enum class Interpolation { Slerp, Linear };

struct Keyframe {
  double time = 0.0;                                             ///< [s]
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();           ///< T_k [m]
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  ///< R_k
};

class KeyframeMotion final : public Motion {
 public:
  /// At least two keys with strictly increasing times (std::invalid_argument otherwise).
  KeyframeMotion(std::vector<Keyframe> keys, Interpolation interpolation);

  void evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                sdk::Positions& velocities) const override;

  const std::vector<Keyframe>& keys() const { return m_keys; }
  Interpolation interpolation() const { return m_interpolation; }

 private:
  /// Per segment k (from key k to k+1), precomputed once.
  struct Segment {
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< a, body frame of key k
    double angle = 0.0;                               ///< θ ∈ [0, π]
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();  ///< world angular velocity [rad/s]
  };
  /// Index k of the segment holding t, or -1 before the first key, or the last key's
  /// index from then on (both: the pose holds).
  int locate(double t) const;
  void hold(int key, const sdk::Positions& rest, sdk::Positions& positions,
            sdk::Positions& velocities) const;

  std::vector<Keyframe> m_keys;
  std::vector<Segment> m_segments;
  Interpolation m_interpolation;
};

}  // namespace shellflow::kinematic_shell
