// Closest points between points, segments and triangles: known answers, degenerate
// input, and the segment–triangle distance against dense sampling.

#include "shellflow/geometry/triangle_distance.hpp"

#include <gtest/gtest.h>

#include <random>

namespace shellflow::geometry {
namespace {

/// Round-off of a few operations on unit coordinates.
constexpr double kRoundOff = 1e-14;

const TriangleCorners kTri = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                              Eigen::Vector3d(0, 1, 0)};

TEST(TriangleDistance, PointKnownAnswers) {
  // Above the face, beyond an edge, beyond a vertex.
  EXPECT_NEAR(point_triangle_distance2({0.2, 0.2, 0.5}, kTri), 0.25, kRoundOff);
  EXPECT_NEAR(point_triangle_distance2({0.5, -0.3, 0.4}, kTri), 0.25, kRoundOff);
  EXPECT_NEAR(point_triangle_distance2({-0.3, -0.4, 0}, kTri), 0.25, kRoundOff);
  const TrianglePoint cp = closest_point_on_triangle({0.8, 0.8, 1.0}, kTri);
  EXPECT_NEAR((cp.point - Eigen::Vector3d(0.5, 0.5, 0)).norm(), 0.0, kRoundOff);
  EXPECT_NEAR((cp.barycentric - Eigen::Vector3d(0, 0.5, 0.5)).norm(), 0.0, kRoundOff);
}

TEST(TriangleDistance, DegenerateTriangleIsItsEdges) {
  const TriangleCorners line = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0),
                                Eigen::Vector3d(1, 0, 0)};
  EXPECT_NEAR(point_triangle_distance2({1.5, 0.3, 0.4}, line), 0.25, kRoundOff);
  const TrianglePoint cp = closest_point_on_triangle({1.5, 0.3, 0.4}, line);
  EXPECT_TRUE(cp.point.allFinite());
  EXPECT_NEAR(cp.barycentric.sum(), 1.0, kRoundOff);
  const TriangleCorners dot = {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, 1, 1),
                               Eigen::Vector3d(1, 1, 1)};
  EXPECT_NEAR(point_triangle_distance2({1, 1, 2}, dot), 1.0, kRoundOff);
  EXPECT_TRUE(segment_near_triangle({0, 1, 1}, {2, 1, 1}, dot, 1e-12));
  EXPECT_FALSE(segment_near_triangle({0, 1, 1.1}, {2, 1, 1.1}, dot, 0.09));
}

TEST(TriangleDistance, SegmentKnownAnswers) {
  // Crossing the face: distance 0 at s = 0.5.
  const SegmentTriangleClosest cross =
      closest_segment_triangle({0.2, 0.2, -1}, {0.2, 0.2, 1}, kTri);
  EXPECT_NEAR(cross.distance2, 0.0, kRoundOff);
  EXPECT_NEAR(cross.s, 0.5, kRoundOff);
  // Parallel above the face at height 0.3.
  EXPECT_NEAR(closest_segment_triangle({-1, 0.2, 0.3}, {2, 0.2, 0.3}, kTri).distance2, 0.09,
              kRoundOff);
  // Skew to the hypotenuse edge: the line x + y = 1.5 at z = 0 is sqrt(0.125) from it.
  EXPECT_NEAR(closest_segment_triangle({1.5, 0, 0}, {0, 1.5, 0}, kTri).distance2, 0.125, kRoundOff);
}

// The exact segment–triangle distance is never above the distance between any sampled
// pair, and comes within the sampling resolution of the best sampled pair.
TEST(TriangleDistance, SegmentMatchesDenseSampling) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto rv = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  constexpr int kSamples = 60;
  for (int trial = 0; trial < 300; ++trial) {
    const TriangleCorners c = {rv(), rv(), rv()};
    const Eigen::Vector3d a = rv(), b = rv();
    const double exact = std::sqrt(closest_segment_triangle(a, b, c).distance2);
    double sampled = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= kSamples; ++i) {
      const Eigen::Vector3d x = a + (double(i) / kSamples) * (b - a);
      sampled = std::min(sampled, std::sqrt(point_triangle_distance2(x, c)));
    }
    EXPECT_LE(exact, sampled + kRoundOff);
    // Sampling the segment every |b - a| / 60 misses the minimum by at most half a step.
    EXPECT_GE(exact, sampled - 0.5 * (b - a).norm() / kSamples - kRoundOff);
    // segment_near_triangle agrees with the distance on both sides of a margin.
    EXPECT_TRUE(segment_near_triangle(a, b, c, exact * 1.001 + 1e-12));
    if (exact > 1e-6) {
      EXPECT_FALSE(segment_near_triangle(a, b, c, exact * 0.999));
    }
  }
}

}  // namespace
}  // namespace shellflow::geometry
