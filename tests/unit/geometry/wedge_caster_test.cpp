// WedgeCaster (§3, Fig. 3): no false "visible" through closed and folded shells, far
// segments always visible, and the wedge thickness semantics (ε/2 each side, ε' = 2ε).

#include "shellflow/geometry/wedge_caster.hpp"

#include <gtest/gtest.h>

#include <random>

#include "test_meshes.hpp"

namespace shellflow::geometry {
namespace {

using test::Mesh;

/// Wedge thickness used by most tests; the 2011 PhysBAM value is 1e-3 × dx, and these
/// meshes have unit size with dx-like features ~0.05, so 1e-4 is of that order.
constexpr double kEpsilon = 1e-4;

Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
}

/// Counts "visible" answers for segments from strictly inside to strictly outside a
/// closed convex mesh centred at the origin. `inner` bounds the inside region (a ball
/// inside the mesh), `outer` the outside one (a ball radius beyond the mesh).
/// A quarter of the segments are random, a quarter aim exactly at a vertex, a quarter
/// at a random point of an edge, and a quarter at a point of a triangle's plane that lies
/// on the triangle's edge extended (grazing the edge from within the plane's normal
/// direction). Returns the number of false visibles.
int false_visibles_closed(const Mesh& mesh, double inner, double outer, int segments,
                          std::uint64_t seed) {
  const TriangleMesh view(mesh.positions, mesh.triangles);
  const TriangleBvh bvh(view);
  const WedgeCaster caster(bvh, kEpsilon);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> pick_node(0, view.node_count() - 1);
  std::uniform_int_distribution<int> pick_tri(0, view.triangle_count() - 1);
  int visible = 0;
  for (int s = 0; s < segments; ++s) {
    const Eigen::Vector3d a = inner * std::cbrt(unit(rng)) * random_unit(rng);
    Eigen::Vector3d target;
    switch (s % 4) {
      case 0:
        target = random_unit(rng);
        break;
      case 1:
        target = view.node(pick_node(rng));
        break;
      case 2: {
        const TriangleCorners c = view.corners(pick_tri(rng));
        const int e = s / 4 % 3;
        target = c[e] + unit(rng) * (c[(e + 1) % 3] - c[e]);
        break;
      }
      default: {
        const TriangleCorners c = view.corners(pick_tri(rng));
        target = (c[0] + c[1] + c[2]) / 3.0;
        break;
      }
    }
    // Extend the ray from a through the target to the outside ball.
    const Eigen::Vector3d dir = (target - a).normalized();
    const Eigen::Vector3d b = a + (outer + a.norm()) * dir;
    if (caster.classify(a, b) == Visibility::Visible) ++visible;
    // And the reverse direction: outside looking in.
    if (caster.classify(b, a) == Visibility::Visible) ++visible;
  }
  return visible;
}

// Icosphere radius 1: its faces are at least cos(largest vertex angle) from the centre
// (> 0.79 for level 0), so the ball of radius 0.75 is strictly inside; all vertices lie
// on the unit sphere, so |x| > 1.05 is strictly outside.
TEST(WedgeCaster, NoFalseVisibleThroughClosedSphere) {
  for (int level = 0; level <= 4; ++level) {
    const Mesh sphere = test::make_icosphere(1.0, level);
    EXPECT_EQ(false_visibles_closed(sphere, 0.75, 1.05, 50'000, 11 + level), 0)
        << "level " << level;
  }
}

// Box [-0.5, 0.5]^3: ball 0.45 strictly inside; beyond the circumradius 0.87 outside.
TEST(WedgeCaster, NoFalseVisibleThroughClosedBox) {
  for (const int divisions : {1, 2, 5, 16, 40}) {
    const Mesh box = test::make_closed_box(Eigen::Vector3d::Ones(), divisions);
    EXPECT_EQ(false_visibles_closed(box, 0.45, 0.9, 50'000, 97 + divisions), 0)
        << "divisions " << divisions;
  }
}

// Segments parallel to a face, just beneath it (depth 0..3ε), leaving through the
// perpendicular side face next to the box edge, and segments lying in the planes of
// grid lines on the faces (they cross the surface exactly along triangle edges).
TEST(WedgeCaster, NoFalseVisibleAlongBoxFacesAndEdges) {
  for (const int divisions : {1, 4, 10}) {
    const Mesh box = test::make_closed_box(Eigen::Vector3d::Ones(), divisions);
    const TriangleMesh view(box.positions, box.triangles);
    const TriangleBvh bvh(view);
    const WedgeCaster caster(bvh, kEpsilon);
    std::mt19937_64 rng(5 + divisions);
    std::uniform_real_distribution<double> in(-0.5, 0.5);
    std::uniform_real_distribution<double> depth(0.0, 3.0 * kEpsilon);
    std::uniform_int_distribution<int> line(0, divisions);
    int visible = 0;
    for (int s = 0; s < 100'000; ++s) {
      Eigen::Vector3d a;
      Eigen::Vector3d b;
      if (s % 2 == 0) {
        // Under the top face (z = 0.5 - depth), running in +x out through x = 0.5.
        a = {in(rng)*0.9, in(rng), 0.5 - depth(rng)};
        if (s % 4 == 0) a.y() = -0.5 + line(rng) / double(divisions);  // on a grid line
        b = a + Eigen::Vector3d(2.0, 0.0, 0.0);
      } else {
        // In the plane y = grid line: from inside to outside in a random in-plane direction.
        const double y = -0.5 + line(rng) / double(divisions);
        a = {0.45 * in(rng), std::clamp(y, -0.45, 0.45), 0.45 * in(rng)};
        const double angle = 2.0 * M_PI * (in(rng) + 0.5);
        b = Eigen::Vector3d(a.x() + 2.0 * std::cos(angle), y, a.z() + 2.0 * std::sin(angle));
        a.y() = y;
        if (std::abs(y) >= 0.5) continue;  // the plane of a face: not strictly inside
      }
      if (caster.classify(a, b) == Visibility::Visible) ++visible;
    }
    EXPECT_EQ(visible, 0) << "divisions " << divisions;
  }
}

// A cloth folded onto itself with the two sheets 0.1ε apart: from above both sheets to
// below both, nothing is visible; including rays lying in the sheet's own plane.
TEST(WedgeCaster, NoFalseVisibleThroughFoldedCloth) {
  const Mesh cloth = test::make_folded_cloth(41, 0.1 * kEpsilon);
  const TriangleMesh view(cloth.positions, cloth.triangles);
  const TriangleBvh bvh(view);
  const WedgeCaster caster(bvh, kEpsilon);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> in(0.0, 1.0);
  std::uniform_real_distribution<double> height(kEpsilon, 0.3);
  std::uniform_int_distribution<int> pick_node(0, view.node_count() - 1);
  int visible = 0;
  for (int s = 0; s < 200'000; ++s) {
    Eigen::Vector3d a(in(rng), in(rng), height(rng));
    Eigen::Vector3d b(in(rng), in(rng), -height(rng));
    if (s % 3 == 1) b = a + 2.0 * (view.node(pick_node(rng)) - a);  // through a node
    if (s % 3 == 2) {
      // In the plane of the lower sheet, crossing the cloth region.
      a = {-0.5, in(rng), 0.0};
      b = {1.5, in(rng), 0.0};
    }
    if (caster.classify(a, b) == Visibility::Visible) ++visible;
    if (caster.classify(b, a) == Visibility::Visible) ++visible;
  }
  EXPECT_EQ(visible, 0);
}

// Segments that stay away from every triangle are visible: inside the sphere's inner
// ball, and outside its bounding box.
TEST(WedgeCaster, FarSegmentsAreVisible) {
  const Mesh sphere = test::make_icosphere(1.0, 3);
  const TriangleMesh view(sphere.positions, sphere.triangles);
  const TriangleBvh bvh(view);
  const WedgeCaster caster(bvh, kEpsilon);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int not_visible = 0;
  for (int s = 0; s < 100'000; ++s) {
    // Inner ball 0.9 (faces are > 0.98 from the centre at level 3).
    const Eigen::Vector3d a = 0.9 * std::cbrt(unit(rng)) * random_unit(rng);
    const Eigen::Vector3d b = 0.9 * std::cbrt(unit(rng)) * random_unit(rng);
    if (caster.classify(a, b) != Visibility::Visible) ++not_visible;
    // The half-space x > 1.01 is outside the sphere (|x| <= 1 on the mesh).
    const Eigen::Vector3d c(1.01 + unit(rng), 4.0 * unit(rng) - 2.0, 4.0 * unit(rng) - 2.0);
    const Eigen::Vector3d d(1.01 + unit(rng), 4.0 * unit(rng) - 2.0, 4.0 * unit(rng) - 2.0);
    if (caster.classify(c, d) != Visibility::Visible) ++not_visible;
  }
  EXPECT_EQ(not_visible, 0);
}

// The wedge is exactly ε/2 thick on each side of a face: a segment parallel to a sheet at
// height 0.51ε sees through, at 0.49ε it is blocked; with ε' = 2ε (§4.1) both are blocked.
// A ±1% margin on ε/2 is far above round-off (1e-16) at unit coordinates.
TEST(WedgeCaster, ThicknessIsHalfEpsilonEachSide) {
  const Mesh sheet = test::make_sheet(1.0, 1.0, 11, 11);
  const TriangleMesh view(sheet.positions, sheet.triangles);
  const TriangleBvh bvh(view);
  const WedgeCaster caster(bvh, kEpsilon);
  for (const double sign : {1.0, -1.0}) {
    const Eigen::Vector3d a0(0.1, 0.37, sign * 0.51 * kEpsilon),
        b0(0.9, 0.63, sign * 0.51 * kEpsilon);
    EXPECT_EQ(caster.classify(a0, b0), Visibility::Visible);
    EXPECT_NE(caster.classify(a0, b0, caster.semi_lagrangian_epsilon()), Visibility::Visible);
    const Eigen::Vector3d a1(0.1, 0.37, sign * 0.49 * kEpsilon),
        b1(0.9, 0.63, sign * 0.49 * kEpsilon);
    EXPECT_NE(caster.classify(a1, b1), Visibility::Visible);
  }
  // Beyond the sheet's edge, the rounded edge is ε/2 too: passing 0.51ε past x = 1 is
  // visible, 0.49ε is not.
  EXPECT_EQ(caster.classify({1.0 + 0.51 * kEpsilon, 0.5, -1.0}, {1.0 + 0.51 * kEpsilon, 0.5, 1.0}),
            Visibility::Visible);
  EXPECT_NE(caster.classify({1.0 + 0.49 * kEpsilon, 0.5, -1.0}, {1.0 + 0.49 * kEpsilon, 0.5, 1.0}),
            Visibility::Visible);
  // Past a corner vertex along the diagonal: the ball of radius ε/2.
  const Eigen::Vector3d out = Eigen::Vector3d(1, 1, 0).normalized();
  const Eigen::Vector3d corner(1, 1, 0);
  EXPECT_EQ(caster.classify(corner + 0.51 * kEpsilon * out + Eigen::Vector3d(0, 0, -1),
                            corner + 0.51 * kEpsilon * out + Eigen::Vector3d(0, 0, 1)),
            Visibility::Visible);
  EXPECT_NE(caster.classify(corner + 0.49 * kEpsilon * out + Eigen::Vector3d(0, 0, -1),
                            corner + 0.49 * kEpsilon * out + Eigen::Vector3d(0, 0, 1)),
            Visibility::Visible);
}

// Fig. 3 right: B behind the sheet is occluded, B within ε/2 of it is inside, B on the
// same side is visible; first_hit reports the crossing point's barycentrics.
TEST(WedgeCaster, ClassifiesInsideOccludedVisible) {
  const Mesh sheet = test::make_sheet(1.0, 1.0, 5, 5);
  const TriangleMesh view(sheet.positions, sheet.triangles);
  const TriangleBvh bvh(view);
  const WedgeCaster caster(bvh, kEpsilon);
  const Eigen::Vector3d a(0.3, 0.6, 0.2);
  EXPECT_EQ(caster.classify(a, {0.35, 0.55, -0.1}), Visibility::Occluded);
  EXPECT_EQ(caster.classify(a, {0.35, 0.55, 0.3 * kEpsilon}), Visibility::Inside);
  EXPECT_EQ(caster.classify(a, {0.35, 0.55, 0.1}), Visibility::Visible);
  EXPECT_TRUE(caster.inside({0.35, 0.55, -0.3 * kEpsilon}));
  EXPECT_FALSE(caster.inside({0.35, 0.55, -0.6 * kEpsilon}));

  // Straight down from (0.3, 0.6, 0.2): the closest approach is at z = 0, s = 0.2/0.4.
  const auto hit = caster.first_hit(a, {0.3, 0.6, -0.2});
  ASSERT_TRUE(hit.has_value());
  const TriangleCorners c = view.corners(hit->triangle);
  const Eigen::Vector3d p =
      hit->barycentric[0] * c[0] + hit->barycentric[1] * c[1] + hit->barycentric[2] * c[2];
  // Round-off of a handful of operations on unit coordinates.
  EXPECT_NEAR(p.x(), 0.3, 1e-12);
  EXPECT_NEAR(p.y(), 0.6, 1e-12);
  EXPECT_NEAR(hit->s, 0.5, 1e-12);
  EXPECT_FALSE(caster.first_hit(a, {0.4, 0.4, 0.1}).has_value());
}

// Several shells: a ray blocked by the second shell only is not visible.
TEST(WedgeCaster, SeveralShells) {
  const Mesh low = test::make_sheet(1.0, 1.0, 3, 3);
  Mesh high = test::make_sheet(1.0, 1.0, 3, 3);
  high.positions.col(2).array() += 0.5;
  const TriangleMesh v0(low.positions, low.triangles), v1(high.positions, high.triangles);
  const TriangleBvh b0(v0), b1(v1);
  const WedgeCaster caster({&b0, &b1}, kEpsilon);
  EXPECT_EQ(caster.classify({0.5, 0.5, 0.25}, {0.5, 0.5, 0.75}), Visibility::Occluded);
  EXPECT_EQ(caster.classify({0.5, 0.5, 0.25}, {0.5, 0.5, 0.45}), Visibility::Visible);
  const auto hit = caster.first_hit({0.5, 0.5, 0.25}, {0.5, 0.5, 0.75});
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->shell, 1);
}

}  // namespace
}  // namespace shellflow::geometry
