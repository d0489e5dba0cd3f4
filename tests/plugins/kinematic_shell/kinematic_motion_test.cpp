// Scripted motions against closed-form positions, finite-difference velocities, rigidity
// and the hold before and after the keys.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/kinematic_shell/analytic_motion.hpp"
#include "shellflow/kinematic_shell/keyframe_motion.hpp"
#include "shellflow/kinematic_shell/wave_motion.hpp"

namespace shellflow::kinematic_shell {
namespace {

constexpr double kPi = std::numbers::pi;
// Positions are O(1–10) m built from a handful of products: round-off ≈ 1e-15, so 1e-12
// relative leaves three orders of margin and still fails on any formula error.
constexpr double kRoundOff = 1e-12;

sdk::Positions sample_nodes() {
  auto mesh = geometry::make_box(Eigen::Vector3d(1.0, 0.6, 0.4), 2);
  mesh.positions.rowwise() += Eigen::RowVector3d(0.3, -0.2, 0.5);  // off the origin
  return mesh.positions;
}

/// Rodrigues' formula, written independently of Eigen's AngleAxis.
Eigen::Vector3d rodrigues(const Eigen::Vector3d& axis, double angle, const Eigen::Vector3d& v) {
  const Eigen::Vector3d k = axis.normalized();
  return v * std::cos(angle) + k.cross(v) * std::sin(angle) + k * k.dot(v) * (1 - std::cos(angle));
}

double max_row_distance(const sdk::Positions& a, const sdk::Positions& b) {
  return (a - b).rowwise().norm().maxCoeff();
}

/// max over nodes of |v(t) − (x(t+h) − x(t−h)) / 2h|.
double fd_velocity_error(const Motion& motion, const sdk::Positions& rest, double t, double h) {
  sdk::Positions x, v, xp, xm, unused;
  motion.evaluate(t, rest, x, v);
  motion.evaluate(t + h, rest, xp, unused);
  motion.evaluate(t - h, rest, xm, unused);
  return max_row_distance(v, (xp - xm) / (2 * h));
}

// Analytic ----------------------------------------------------------------------------------

TEST(AnalyticMotion, MatchesTheClosedFormAtManyTimes) {
  const Eigen::Vector3d v(0.4, -1.0, 0.25), omega(0.3, 1.2, -0.7), c(1.0, 2.0, -0.5);
  const AnalyticMotion motion(v, omega, c);
  const auto rest = sample_nodes();
  sdk::Positions x, u;
  for (double t = -2.0; t <= 6.0; t += 0.37) {
    motion.evaluate(t, rest, x, u);
    for (Eigen::Index i = 0; i < rest.rows(); ++i) {
      const Eigen::Vector3d arm = rodrigues(omega, omega.norm() * t, rest.row(i).transpose() - c);
      const Eigen::Vector3d expected = c + v * t + arm;
      EXPECT_LT((x.row(i).transpose() - expected).norm(), kRoundOff * (1 + expected.norm()))
          << "t = " << t << ", node " << i;
      EXPECT_LT((u.row(i).transpose() - (v + omega.cross(arm))).norm(), kRoundOff * 10);
    }
  }
}

TEST(AnalyticMotion, VelocitiesAreSecondOrderFiniteDifferencesOfPositions) {
  const AnalyticMotion motion({0.4, -1.0, 0.25}, {0.3, 1.2, -0.7}, {1.0, 2.0, -0.5});
  const auto rest = sample_nodes();
  for (double t : {0.0, 0.8, 3.1}) {
    const double e1 = fd_velocity_error(motion, rest, t, 1e-2);
    const double e2 = fd_velocity_error(motion, rest, t, 5e-3);
    // Centered differences: error = |x'''| h²/6 + …, so halving h divides it by 4
    // (round-off ≈ 1e-16/h is 1e-9 of the error here).
    EXPECT_NEAR(e1 / e2, 4.0, 0.05) << "t = " << t;
    EXPECT_LT(e1, 1e-3);
  }
}

TEST(AnalyticMotion, PureTranslationAndPureSpinAreExact) {
  const auto rest = sample_nodes();
  sdk::Positions x, u;
  AnalyticMotion({1, 2, 3}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())
      .evaluate(0.5, rest, x, u);
  EXPECT_LT(max_row_distance(x, rest.rowwise() + Eigen::RowVector3d(0.5, 1, 1.5)), kRoundOff);
  // Half a turn about y through c: x ↦ 2c − x in x and z.
  const Eigen::Vector3d c(1, 0, 1);
  AnalyticMotion(Eigen::Vector3d::Zero(), {0, kPi, 0}, c).evaluate(1.0, rest, x, u);
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    EXPECT_NEAR(x(i, 0), 2 * c.x() - rest(i, 0), kRoundOff * 10);
    EXPECT_NEAR(x(i, 1), rest(i, 1), kRoundOff);
    EXPECT_NEAR(x(i, 2), 2 * c.z() - rest(i, 2), kRoundOff * 10);
  }
}

// Keyframes ---------------------------------------------------------------------------------

Keyframe key(double time, const Eigen::Vector3d& translate, const Eigen::Vector3d& axis,
             double degrees) {
  return {time, translate,
          Eigen::Quaterniond(Eigen::AngleAxisd(degrees * kPi / 180, axis.normalized()))};
}

std::vector<Keyframe> three_keys() {
  return {key(0.5, {0, 0, 0}, {0, 1, 0}, 0), key(1.5, {2, 1, 0}, {1, 1, 0}, 120),
          key(2.25, {1, 3, -1}, {0, 0, 1}, -60)};
}

TEST(KeyframeMotion, SlerpMatchesEigenSlerpAndLinearTranslation) {
  const auto keys = three_keys();
  const KeyframeMotion motion(keys, Interpolation::Slerp);
  const auto rest = sample_nodes();
  sdk::Positions x, u;
  for (double t = 0.5; t < 2.25; t += 0.0625) {
    const size_t k = t < 1.5 ? 0 : 1;
    const double s = (t - keys[k].time) / (keys[k + 1].time - keys[k].time);
    const Eigen::Quaterniond q = keys[k].rotation.slerp(s, keys[k + 1].rotation);
    const Eigen::Vector3d translate = (1 - s) * keys[k].translate + s * keys[k + 1].translate;
    motion.evaluate(t, rest, x, u);
    for (Eigen::Index i = 0; i < rest.rows(); ++i) {
      const Eigen::Vector3d expected = q * Eigen::Vector3d(rest.row(i)) + translate;
      EXPECT_LT((x.row(i).transpose() - expected).norm(), kRoundOff * (1 + expected.norm()))
          << "t = " << t;
    }
  }
}

TEST(KeyframeMotion, SlerpIsRigid) {
  const KeyframeMotion motion(three_keys(), Interpolation::Slerp);
  const auto mesh = geometry::make_sphere(0.5, 1);
  sdk::Positions x, u;
  for (double t = 0.0; t < 3.0; t += 0.11) {
    motion.evaluate(t, mesh.positions, x, u);
    for (Eigen::Index e = 0; e < mesh.triangles.rows(); ++e)
      for (int c = 0; c < 3; ++c) {
        const int a = mesh.triangles(e, c), b = mesh.triangles(e, (c + 1) % 3);
        const double rest_length = (mesh.positions.row(a) - mesh.positions.row(b)).norm();
        EXPECT_NEAR((x.row(a) - x.row(b)).norm(), rest_length, kRoundOff) << "t = " << t;
      }
    // A rigid velocity field: (v_a − v_b) ⟂ (x_a − x_b) for every pair.
    for (Eigen::Index a = 1; a < x.rows(); a += 7)
      EXPECT_NEAR((u.row(a) - u.row(0)).dot(x.row(a) - x.row(0)), 0.0, kRoundOff * 10);
  }
}

TEST(KeyframeMotion, HitsTheKeyPosesAndHoldsBeforeAndAfter) {
  const auto keys = three_keys();
  const auto rest = sample_nodes();
  for (auto interpolation : {Interpolation::Slerp, Interpolation::Linear}) {
    const KeyframeMotion motion(keys, interpolation);
    sdk::Positions x, u;
    for (const auto& k : keys) {
      motion.evaluate(k.time, rest, x, u);
      sdk::Positions pose = rest * k.rotation.toRotationMatrix().transpose();
      pose.rowwise() += k.translate.transpose();
      EXPECT_LT(max_row_distance(x, pose), kRoundOff * 10) << "key at " << k.time;
      // Continuity: just before the key the pose is (almost) there too (slope × 1e-9).
      motion.evaluate(k.time - 1e-9, rest, x, u);
      EXPECT_LT(max_row_distance(x, pose), 1e-7);
    }
    // Hold: exactly the first / last pose with zero velocity.
    sdk::Positions first, last;
    motion.evaluate(keys.front().time, rest, first, u);
    motion.evaluate(keys.back().time, rest, last, u);
    EXPECT_EQ(u.norm(), 0.0) << "at and after the last key the shell is at rest";
    for (double t : {-5.0, 0.0, 0.4999}) {
      motion.evaluate(t, rest, x, u);
      EXPECT_EQ(x, first);
      EXPECT_EQ(u.norm(), 0.0);
    }
    for (double t : {2.25, 2.3, 100.0}) {
      motion.evaluate(t, rest, x, u);
      EXPECT_EQ(x, last);
      EXPECT_EQ(u.norm(), 0.0);
    }
  }
}

TEST(KeyframeMotion, VelocitiesAreSecondOrderFiniteDifferencesInsideSegments) {
  const auto rest = sample_nodes();
  const KeyframeMotion slerp(three_keys(), Interpolation::Slerp);
  for (double t : {0.7, 1.2, 1.9}) {
    const double e1 = fd_velocity_error(slerp, rest, t, 1e-2);
    const double e2 = fd_velocity_error(slerp, rest, t, 5e-3);
    EXPECT_NEAR(e1 / e2, 4.0, 0.05) << "t = " << t;  // O(h²), see the analytic test
  }
  // Linear: straight lines at constant speed, so centered differences are exact up to
  // round-off (≈ 1e-16 · |x| / h).
  const KeyframeMotion linear(three_keys(), Interpolation::Linear);
  for (double t : {0.7, 1.2, 1.9}) EXPECT_LT(fd_velocity_error(linear, rest, t, 1e-2), 1e-11);
}

TEST(KeyframeMotion, LinearMovesEveryNodeOnAStraightLine) {
  const auto keys = three_keys();
  const KeyframeMotion motion(keys, Interpolation::Linear);
  const auto rest = sample_nodes();
  sdk::Positions a, b, m, u;
  motion.evaluate(0.5, rest, a, u);
  motion.evaluate(1.5, rest, b, u);
  motion.evaluate(1.0, rest, m, u);
  EXPECT_LT(max_row_distance(m, 0.5 * (a + b)), kRoundOff * 10);
  EXPECT_LT(max_row_distance(u, b - a), kRoundOff * 10);  // Δt = 1 s
}

TEST(KeyframeMotion, SlerpTakesTheShorterWay) {
  // 0° → 270° about y is a −90° turn the shorter way: at s = 1/2 the pose is −45°.
  const KeyframeMotion motion({key(0, {0, 0, 0}, {0, 1, 0}, 0), key(1, {0, 0, 0}, {0, 1, 0}, 270)},
                              Interpolation::Slerp);
  sdk::Positions rest(1, 3), x, u;
  rest << 1, 0, 0;
  motion.evaluate(0.5, rest, x, u);
  const Eigen::Vector3d expected = rodrigues({0, 1, 0}, -kPi / 4, {1, 0, 0});
  EXPECT_LT((x.row(0).transpose() - expected).norm(), kRoundOff);
  EXPECT_NEAR(u.row(0).norm(), kPi / 2, kRoundOff);  // |ω| r = (π/2 rad / 1 s) · 1 m
}

TEST(KeyframeMotion, RejectsFewOrUnorderedKeys) {
  EXPECT_THROW(KeyframeMotion({key(0, {0, 0, 0}, {0, 1, 0}, 0)}, Interpolation::Slerp),
               std::invalid_argument);
  EXPECT_THROW(KeyframeMotion({key(1, {0, 0, 0}, {0, 1, 0}, 0), key(1, {1, 0, 0}, {0, 1, 0}, 0)},
                              Interpolation::Linear),
               std::invalid_argument);
}

// Wave ---------------------------------------------------------------------------------------

WaveParameters sample_wave() {
  WaveParameters p;
  p.amplitude = 0.08;
  p.wave_vector = Eigen::Vector3d(0.0, 2 * kPi, kPi);
  p.angular_frequency = 3.0;
  p.phase = 0.4;
  p.direction = Eigen::Vector3d(2.0, 0.0, 0.0);  // normalised by the motion
  return p;
}

TEST(WaveMotion, MatchesTheClosedFormAlongTheDirection) {
  const WaveMotion motion(sample_wave());
  const auto rest = sample_nodes();
  sdk::Positions x, v;
  for (double t = 0.0; t <= 3.0; t += 0.29) {
    motion.evaluate(t, rest, x, v);
    for (Eigen::Index i = 0; i < rest.rows(); ++i) {
      const double y = rest(i, 1), z = rest(i, 2);
      const double phase = 2 * kPi * y + kPi * z - 3.0 * t + 0.4;
      EXPECT_NEAR(x(i, 0), rest(i, 0) + 0.08 * std::sin(phase), kRoundOff) << t << " " << i;
      EXPECT_EQ(x(i, 1), rest(i, 1));  // only the x direction moves
      EXPECT_EQ(x(i, 2), rest(i, 2));
      EXPECT_NEAR(v(i, 0), -0.08 * 3.0 * std::cos(phase), kRoundOff);
      EXPECT_EQ(v(i, 1), 0.0);
    }
  }
}

// Central differences of A sin(φ − ωt) err by at most A ω^3 h^2 / 6 (the Taylor remainder;
// 3.6e-7 at h = 1e-3), and the error falls 4x when h halves (second order).
TEST(WaveMotion, VelocitiesAreSecondOrderFiniteDifferencesOfPositions) {
  const WaveMotion motion(sample_wave());
  const auto rest = sample_nodes();
  const double bound = 0.08 * 27.0 * 1e-6 / 6.0;
  for (const double t : {0.0, 0.7, 2.3}) {
    const double e1 = fd_velocity_error(motion, rest, t, 1e-3);
    const double e2 = fd_velocity_error(motion, rest, t, 5e-4);
    EXPECT_LE(e1, 1.001 * bound) << t;
    EXPECT_NEAR(e1 / e2, 4.0, 0.05) << t;
  }
}

TEST(WaveMotion, RejectsAZeroDirectionAndANegativeAmplitude) {
  WaveParameters zero = sample_wave();
  zero.direction.setZero();
  EXPECT_THROW(WaveMotion{zero}, std::invalid_argument);
  WaveParameters negative = sample_wave();
  negative.amplitude = -1.0;
  EXPECT_THROW(WaveMotion{negative}, std::invalid_argument);
}

}  // namespace
}  // namespace shellflow::kinematic_shell
