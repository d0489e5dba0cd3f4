#include "shellflow/kinematic_shell/keyframe_motion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace shellflow::kinematic_shell {

KeyframeMotion::KeyframeMotion(std::vector<Keyframe> keys, Interpolation interpolation)
    : m_keys(std::move(keys)), m_interpolation(interpolation) {
  if (m_keys.size() < 2) throw std::invalid_argument("KeyframeMotion: needs at least two keys");
  for (auto& key : m_keys) key.rotation.normalize();
  for (size_t k = 0; k + 1 < m_keys.size(); ++k) {
    const Keyframe& a = m_keys[k];
    const Keyframe& b = m_keys[k + 1];
    if (!(b.time > a.time))
      throw std::invalid_argument("KeyframeMotion: key times must increase strictly");
    // Relative rotation in key k's frame, the shorter way (w ≥ 0): angle θ ∈ [0, π].
    Eigen::Quaterniond delta = a.rotation.conjugate() * b.rotation;
    if (delta.w() < 0) delta.coeffs() = -delta.coeffs();
    Segment segment;
    const double sin_half = delta.vec().norm();
    if (sin_half > 0) {
      segment.axis = delta.vec() / sin_half;
      segment.angle = 2.0 * std::atan2(sin_half, delta.w());
    }
    // R(s) = R_k exp(s θ [a]×) ⇒ Ṙ R^T = [R_k a θ/Δt]×: ω = R_k a θ / Δt, constant.
    segment.omega = a.rotation * (segment.axis * segment.angle / (b.time - a.time));
    m_segments.push_back(segment);
  }
}

int KeyframeMotion::locate(double t) const {
  if (t < m_keys.front().time) return -1;
  // First key with time > t; the segment starts one before it.
  const auto next = std::upper_bound(m_keys.begin(), m_keys.end(), t,
                                     [](double x, const Keyframe& k) { return x < k.time; });
  return static_cast<int>(next - m_keys.begin()) - 1;
}

void KeyframeMotion::hold(int key, const sdk::Positions& rest, sdk::Positions& positions,
                          sdk::Positions& velocities) const {
  const Eigen::Matrix3d r = m_keys[key].rotation.toRotationMatrix();
  const Eigen::RowVector3d translate = m_keys[key].translate.transpose();
  positions.resize(rest.rows(), 3);
  for (Eigen::Index i = 0; i < rest.rows(); ++i)
    positions.row(i) = rest.row(i) * r.transpose() + translate;
  velocities.setZero(rest.rows(), 3);
}

void KeyframeMotion::evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                              sdk::Positions& velocities) const {
  const int last = static_cast<int>(m_keys.size()) - 1;
  const int k = locate(t);
  if (k < 0) return hold(0, rest, positions, velocities);
  if (k >= last) return hold(last, rest, positions, velocities);

  const Keyframe& a = m_keys[k];
  const Keyframe& b = m_keys[k + 1];
  const double span = b.time - a.time;
  const double s = (t - a.time) / span;
  const Eigen::Vector3d translate = (1.0 - s) * a.translate + s * b.translate;
  const Eigen::Vector3d translate_rate = (b.translate - a.translate) / span;
  positions.resize(rest.rows(), 3);
  velocities.resize(rest.rows(), 3);

  if (m_interpolation == Interpolation::Slerp) {
    const Segment& segment = m_segments[k];
    const Eigen::Matrix3d r =
        (a.rotation * Eigen::Quaterniond(Eigen::AngleAxisd(s * segment.angle, segment.axis)))
            .toRotationMatrix();
    for (Eigen::Index i = 0; i < rest.rows(); ++i) {
      const Eigen::Vector3d rotated = r * rest.row(i).transpose();
      positions.row(i) = (rotated + translate).transpose();
      velocities.row(i) = (segment.omega.cross(rotated) + translate_rate).transpose();
    }
    return;
  }
  // Linear: x = (1−s) P_k(x0) + s P_{k+1}(x0), ẋ = (P_{k+1}(x0) − P_k(x0)) / Δt.
  const Eigen::Matrix3d ra = a.rotation.toRotationMatrix();
  const Eigen::Matrix3d rb = b.rotation.toRotationMatrix();
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const Eigen::Vector3d x0 = rest.row(i).transpose();
    const Eigen::Vector3d pa = ra * x0 + a.translate;
    const Eigen::Vector3d pb = rb * x0 + b.translate;
    positions.row(i) = ((1.0 - s) * pa + s * pb).transpose();
    velocities.row(i) = ((pb - pa) / span).transpose();
  }
}

}  // namespace shellflow::kinematic_shell
