// Swept-point invalidation (§3): cubic coplanarity times with robust root isolation,
// analytic cases with known answers, and a randomized comparison against fine time
// sampling.

#include "shellflow/geometry/swept_point.hpp"

#include <gtest/gtest.h>

#include <random>

#include "shellflow/geometry/triangle_distance.hpp"

namespace shellflow::geometry {
namespace {

/// Distance tolerance of the swept test in these unit-size cases: far above round-off
/// (1e-16) and far below every geometric margin used below (>= 1e-3).
constexpr double kTolerance = 1e-9;
/// Root times are bisected to ~1e-15; a few ulps of the cubic's coefficients of order 1
/// move a simple root by ~1e-15 / |f'|, so 1e-12 is a safe bound here.
constexpr double kTimeTolerance = 1e-12;

TriangleCorners translate(const TriangleCorners& c, const Eigen::Vector3d& d) {
  return {c[0] + d, c[1] + d, c[2] + d};
}

const TriangleCorners kUnit = {Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(2, -1, 0),
                               Eigen::Vector3d(-1, 2, 0)};

TEST(CubicRoots, KnownRootsAndTouch) {
  // (t - 0.2)(t - 0.5)(t - 0.9) = t^3 - 1.6 t^2 + 0.73 t - 0.09
  const NearRoots r = cubic_near_roots({-0.09, 0.73, -1.6, 1.0}, 1e-14);
  ASSERT_EQ(r.count, 3);
  EXPECT_NEAR(r.times[0], 0.2, kTimeTolerance);
  EXPECT_NEAR(r.times[1], 0.5, kTimeTolerance);
  EXPECT_NEAR(r.times[2], 0.9, kTimeTolerance);
  // Double root (t - 0.3)^2 = t^2 - 0.6 t + 0.09: no sign change, found as a near-root
  // at the critical point.
  const NearRoots d = cubic_near_roots({0.09, -0.6, 1.0, 0.0}, 1e-14);
  ASSERT_EQ(d.count, 1);
  EXPECT_NEAR(d.times[0], 0.3, kTimeTolerance);
  // (t - 0.3)^2 + 1e-3 never comes within 1e-6 of zero.
  EXPECT_EQ(cubic_near_roots({0.091, -0.6, 1.0, 0.0}, 1e-6).count, 0);
  EXPECT_TRUE(cubic_near_roots({1e-20, 0.0, -1e-20, 0.0}, 1e-15).everywhere_near_zero);
}

TEST(SweptPoint, CrossedAtKnownTime) {
  // The triangle moves from z = -1 to z = +1; the point at z = 0.25 is crossed at 0.625.
  const TriangleCorners start = translate(kUnit, {0, 0, -1});
  const TriangleCorners end = translate(kUnit, {0, 0, 1});
  const auto t = triangle_sweeps_point({0.1, 0.2, 0.25}, start, end, kTolerance);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.625, kTimeTolerance);
  // Beside the triangle (x + y > 1 is outside it): the plane passes, the triangle does not.
  EXPECT_FALSE(triangle_sweeps_point({0.6, 0.6, 0.25}, start, end, kTolerance).has_value());
  // Stopping short of the point: not crossed.
  EXPECT_FALSE(
      triangle_sweeps_point({0.1, 0.2, 0.25}, start, translate(kUnit, {0, 0, 0.2}), kTolerance)
          .has_value());
}

TEST(SweptPoint, GrazingPass) {
  // The triangle comes up to z = -1e-3 below the point and goes back down
  // (linear motion cannot turn around, so it grazes by tilting instead: one corner
  // rises, the plane swings under the point without reaching it).
  const Eigen::Vector3d p(0.0, 0.0, 0.0);
  const TriangleCorners start = translate(kUnit, {0, 0, -1e-3});
  const TriangleCorners end = {Eigen::Vector3d(-1, -1, -1e-3), Eigen::Vector3d(2, -1, -1e-3),
                               Eigen::Vector3d(-1, 2, -0.5)};
  EXPECT_FALSE(triangle_sweeps_point(p, start, end, kTolerance).has_value());
  // A triangle passing 1e-3 beside the point (its edge x = -1 slides along y) never
  // contains it although its plane does at t = 0.5.
  const TriangleCorners s2 = translate(kUnit, {1.001, 0, -1});
  const TriangleCorners e2 = translate(kUnit, {1.001, 0, 1});
  EXPECT_FALSE(triangle_sweeps_point(p, s2, e2, kTolerance).has_value());
  // The same pass 1e-3 to the other side does cross.
  const TriangleCorners s3 = translate(kUnit, {0.999, 0, -1});
  const TriangleCorners e3 = translate(kUnit, {0.999, 0, 1});
  const auto t = triangle_sweeps_point(p, s3, e3, kTolerance);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.5, kTimeTolerance);
}

TEST(SweptPoint, MovingParallelToItself) {
  // In its own plane through the point: the triangle slides over it (f ≡ 0).
  const Eigen::Vector3d p(0.0, 0.0, 0.0);
  const auto in_plane = triangle_sweeps_point(p, translate(kUnit, {-5, 0, 0}),
                                              translate(kUnit, {5, 0, 0}), kTolerance);
  ASSERT_TRUE(in_plane.has_value());
  // Corner x = -1 .. edge x + y = 1 at y = 0: the point enters when the edge x + y = 1
  // (shifted by -5 + 10 t) reaches x = 0: 1 - 5 + 10 t = 0, t = 0.4.
  EXPECT_NEAR(*in_plane, 0.4, 1e-9);
  // In its plane but sliding past the point: never contains it.
  EXPECT_FALSE(triangle_sweeps_point(p, translate(kUnit, {-5, 3, 0}), translate(kUnit, {5, 3, 0}),
                                     kTolerance)
                   .has_value());
  // In a parallel plane 1e-3 away: never coplanar.
  EXPECT_FALSE(triangle_sweeps_point(p, translate(kUnit, {-5, 0, 1e-3}),
                                     translate(kUnit, {5, 0, 1e-3}), kTolerance)
                   .has_value());
}

TEST(SweptPoint, DegenerateZeroAreaTriangle) {
  // A "triangle" collapsed onto a segment from (-1, 0) to (1, 0) sweeping z: -1 → 1.
  const TriangleCorners line = {Eigen::Vector3d(-1, 0, -1), Eigen::Vector3d(1, 0, -1),
                                Eigen::Vector3d(0, 0, -1)};
  const auto t =
      triangle_sweeps_point({0.3, 0.0, 0.0}, line, translate(line, {0, 0, 2}), kTolerance);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 0.5, 1e-9);
  EXPECT_FALSE(triangle_sweeps_point({0.3, 1e-3, 0.0}, line, translate(line, {0, 0, 2}), kTolerance)
                   .has_value());
  // Collapsed onto a single point passing exactly through p, and one missing it.
  const TriangleCorners dot = {Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, -1),
                               Eigen::Vector3d(0, 0, -1)};
  EXPECT_TRUE(triangle_sweeps_point({0, 0, 0.5}, dot, translate(dot, {0, 0, 2}), kTolerance));
  EXPECT_FALSE(triangle_sweeps_point({1e-3, 0, 0.5}, dot, translate(dot, {0, 0, 2}), kTolerance));
}

TEST(SweptPoint, RotatingThroughThePoint) {
  // A triangle with a corner on the y axis swings its other corners from the x axis to
  // the z axis: x_i(t) = (1 - t, ±0.5, t) (linear interpolation of a 90° turn). Its
  // plane has normal (t, 0, t - 1), so p = (0.3, 0, 0.6) is coplanar at t = 2/3, where
  // p = 0.9 × (1/3, 0, 2/3) lies inside.
  const TriangleCorners start = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0.5, 0),
                                 Eigen::Vector3d(1, -0.5, 0)};
  const TriangleCorners end = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0.5, 1),
                               Eigen::Vector3d(0, -0.5, 1)};
  const auto t = triangle_sweeps_point({0.3, 0.0, 0.6}, start, end, kTolerance);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, 2.0 / 3.0, kTimeTolerance);
  // (0.9, 0, 0.9) is coplanar at t = 1/2, where it is 1.8× beyond the far edge.
  EXPECT_FALSE(triangle_sweeps_point({0.9, 0.0, 0.9}, start, end, kTolerance).has_value());
}

TEST(SweptPoint, InvalidatedInsideWedgeAtStartOrEnd) {
  const double epsilon = 1e-2;
  const TriangleCorners start = kUnit;
  const TriangleCorners end = translate(kUnit, {0, 0, 1});
  // 0.4ε below the start position: inside the start wedge, never swept.
  EXPECT_TRUE(point_invalidated({0.1, 0.1, -0.4 * epsilon}, start, end, epsilon, kTolerance));
  EXPECT_FALSE(triangle_sweeps_point({0.1, 0.1, -0.4 * epsilon}, start, end, kTolerance));
  EXPECT_TRUE(point_invalidated({0.1, 0.1, 1 + 0.4 * epsilon}, start, end, epsilon, kTolerance));
  EXPECT_FALSE(point_invalidated({0.1, 0.1, -0.6 * epsilon}, start, end, epsilon, kTolerance));
  EXPECT_FALSE(point_invalidated({0.1, 0.1, 1 + 0.6 * epsilon}, start, end, epsilon, kTolerance));
}

/// Reference by time sampling: returns +1 if the point is crossed clearly inside the
/// triangle (margin `m` from its boundary at the crossing), -1 if the signed plane
/// distance never changes sign or every crossing is clearly outside, 0 if ambiguous.
int sampled_reference(const Eigen::Vector3d& p, const TriangleCorners& s, const TriangleCorners& e,
                      int samples, double m) {
  const auto at = [&](double t) {
    return TriangleCorners{(1 - t) * s[0] + t * e[0], (1 - t) * s[1] + t * e[1],
                           (1 - t) * s[2] + t * e[2]};
  };
  const auto signed_distance = [&](const TriangleCorners& c) {
    const Eigen::Vector3d n = (c[1] - c[0]).cross(c[2] - c[0]);
    return n.normalized().dot(p - c[0]);
  };
  bool ambiguous = false;
  double d0 = signed_distance(at(0.0));
  for (int k = 1; k <= samples; ++k) {
    const double t1 = double(k) / samples;
    const double d1 = signed_distance(at(t1));
    if ((d0 < 0) != (d1 < 0)) {
      const double t0 = double(k - 1) / samples;
      const double tc = t0 + (t1 - t0) * d0 / (d0 - d1);
      const TriangleCorners c = at(tc);
      // In-plane distance to the triangle's boundary, signed: inside if all edge
      // distances positive.
      const Eigen::Vector3d n = (c[1] - c[0]).cross(c[2] - c[0]).normalized();
      const Eigen::Vector3d q = p - n.dot(p - c[0]) * n;
      double inside = std::numeric_limits<double>::infinity();
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d edge = c[(i + 1) % 3] - c[i];
        inside = std::min(inside, n.cross(edge).normalized().dot(q - c[i]));
      }
      if (inside > m) return 1;
      if (inside > -m) ambiguous = true;
    }
    d0 = d1;
  }
  return ambiguous ? 0 : -1;
}

// Random triangles with random linear motions and random points: the robust test and a
// 4000-sample time reference agree wherever the reference is unambiguous (crossing
// farther than 1e-3 from the triangle's boundary, and the plane distance sampled away
// from tangencies by requiring the motion to be no faster than the sampling resolves).
TEST(SweptPoint, RandomizedAgainstTimeSampling) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto rv = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  int crossed = 0, missed = 0, disagreements = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const TriangleCorners s = {rv(), rv(), rv()};
    const Eigen::Vector3d shift = rv();
    TriangleCorners e = {s[0] + shift + 0.5 * rv(), s[1] + shift + 0.5 * rv(),
                         s[2] + shift + 0.5 * rv()};
    const Eigen::Vector3d p = 0.5 * rv() + 0.5 * shift;
    const int reference = sampled_reference(p, s, e, 4000, 1e-3);
    if (reference == 0) continue;
    const bool swept = triangle_sweeps_point(p, s, e, kTolerance).has_value();
    if (swept != (reference > 0)) ++disagreements;
    (reference > 0 ? crossed : missed)++;
  }
  EXPECT_EQ(disagreements, 0);
  // The sample must exercise both outcomes in quantity.
  EXPECT_GT(crossed, 200);
  EXPECT_GT(missed, 200);
}

}  // namespace
}  // namespace shellflow::geometry
