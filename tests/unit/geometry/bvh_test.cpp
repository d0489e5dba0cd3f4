// Box hierarchy (§3): every query agrees with brute force, before and after refit;
// rebuild happens when (and only when) the refit tree degrades; the swept hierarchy
// bounds the triangle at every time of the step.

#include "shellflow/geometry/bvh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "shellflow/geometry/swept_triangle_bvh.hpp"
#include "shellflow/geometry/triangle_bvh.hpp"
#include "test_meshes.hpp"

namespace shellflow::geometry {
namespace {

std::vector<int> sorted(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  return v;
}

void expect_queries_match_brute_force(const TriangleBvh& bvh, std::uint64_t seed) {
  const TriangleMesh& mesh = bvh.mesh();
  std::mt19937_64 rng(seed);
  const Aabb bounds = mesh.bounds();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto random_point = [&] {
    return Eigen::Vector3d(
        bounds.lower.array() +
        Eigen::Array3d(u(rng), u(rng), u(rng)) * (bounds.extent().array() + 0.2) - 0.1);
  };
  for (int q = 0; q < 200; ++q) {
    // Box query.
    const Eigen::Vector3d c = random_point();
    const Aabb box(c.array() - 0.1, c.array() + 0.1);
    std::vector<int> found, expected;
    bvh.triangles_overlapping(box, [&](int t) {
      found.push_back(t);
      return false;
    });
    for (int t = 0; t < mesh.triangle_count(); ++t) {
      if (mesh.box(t).overlaps(box)) expected.push_back(t);
    }
    EXPECT_EQ(sorted(found), expected);
    // Segment query with a radius.
    const Eigen::Vector3d a = random_point(), b = random_point();
    found.clear();
    expected.clear();
    bvh.triangles_near_segment(a, b, 0.01, [&](int t) {
      found.push_back(t);
      return false;
    });
    for (int t = 0; t < mesh.triangle_count(); ++t) {
      if (mesh.box(t).overlaps_segment(a, b, 0.01)) expected.push_back(t);
    }
    EXPECT_EQ(sorted(found), expected);
    // Closest point: same distance as brute force (exactly: same formula, same triangle
    // or an equally close one).
    const Eigen::Vector3d p = random_point();
    const SurfacePoint cp = bvh.closest_point(p);
    double best = std::numeric_limits<double>::infinity();
    for (int t = 0; t < mesh.triangle_count(); ++t) {
      best = std::min(best, point_triangle_distance2(p, mesh.corners(t)));
    }
    EXPECT_EQ(cp.distance2, best);
    EXPECT_NEAR((cp.point - p).squaredNorm(), best, 1e-15);  // round-off of unit coordinates
  }
}

TEST(Bvh, QueriesMatchBruteForce) {
  const test::Mesh sphere = test::make_icosphere(1.0, 3);
  const TriangleBvh bvh(TriangleMesh(sphere.positions, sphere.triangles));
  expect_queries_match_brute_force(bvh, 1);
}

TEST(Bvh, RefitKeepsQueriesExactAndRebuildsOnlyWhenDegraded) {
  test::Mesh cloth = test::make_sheet(1.0, 1.0, 30, 30);
  TriangleBvh bvh(TriangleMesh(cloth.positions, cloth.triangles));
  const int builds = bvh.bvh().build_count();
  const double cost0 = bvh.bvh().cost();
  // A rigid translation keeps every box's shape: the SAH cost is unchanged, no rebuild.
  cloth.positions.col(2).array() += 0.3;
  EXPECT_FALSE(bvh.update(TriangleMesh(cloth.positions, cloth.triangles)));
  EXPECT_NEAR(bvh.bvh().cost(), cost0, 1e-12 * cost0);  // round-off of box areas
  // A gentle wave: refit, queries still exact.
  for (int i = 0; i < cloth.positions.rows(); ++i) {
    cloth.positions(i, 2) += 0.05 * std::sin(6.0 * cloth.positions(i, 0));
  }
  bvh.update(TriangleMesh(cloth.positions, cloth.triangles));
  expect_queries_match_brute_force(bvh, 2);
  // Scrambling the nodes (a tangled mesh) blows up the refit boxes: it must rebuild.
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < cloth.positions.rows(); ++i) {
    cloth.positions.row(i) = Eigen::RowVector3d(u(rng), u(rng), u(rng));
  }
  EXPECT_TRUE(bvh.update(TriangleMesh(cloth.positions, cloth.triangles)));
  EXPECT_GT(bvh.bvh().build_count(), builds);
  EXPECT_LE(bvh.bvh().cost(), TriangleBvh::kDefaultMaxDegradation * bvh.bvh().build_cost());
  expect_queries_match_brute_force(bvh, 3);
}

TEST(Bvh, SweptBoxesContainTheMotion) {
  test::Mesh start = test::make_icosphere(1.0, 2);
  test::Mesh end = start;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 0.2);
  for (int i = 0; i < end.positions.rows(); ++i) {
    end.positions.row(i) += Eigen::RowVector3d(0.5 + g(rng), g(rng), g(rng));
  }
  const TriangleMesh m0(start.positions, start.triangles), m1(end.positions, end.triangles);
  const SweptTriangleBvh swept(m0, m1);
  for (int t = 0; t < m0.triangle_count(); ++t) {
    const TriangleCorners c0 = m0.corners(t), c1 = m1.corners(t);
    for (const double s : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d x = (1 - s) * c0[k] + s * c1[k];
        ASSERT_TRUE(swept.boxes()[t].contains(x));
        // The hierarchy finds triangle t from a tiny box at x.
        bool seen = false;
        swept.triangles_overlapping(Aabb(x, x), [&](int found) { return seen = (found == t); });
        ASSERT_TRUE(seen);
      }
    }
  }
}

TEST(Aabb, SegmentTestHandlesAxisParallelSegments) {
  const Aabb box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  EXPECT_TRUE(box.overlaps_segment({0.5, 0.5, -1}, {0.5, 0.5, 2}, 0.0));
  EXPECT_FALSE(box.overlaps_segment({1.5, 0.5, -1}, {1.5, 0.5, 2}, 0.0));
  EXPECT_TRUE(box.overlaps_segment({1.5, 0.5, -1}, {1.5, 0.5, 2}, 0.6));
  EXPECT_FALSE(box.overlaps_segment({-2, -2, 0.5}, {-1, -1, 0.5}, 0.0));     // stops short
  EXPECT_TRUE(box.overlaps_segment({0.2, 0.2, 0.2}, {0.2, 0.2, 0.2}, 0.0));  // a point
}

}  // namespace
}  // namespace shellflow::geometry
