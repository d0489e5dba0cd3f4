// preview_writer: the water surface against known answers — the sphere's level set hit
// exactly where φ is linear along the ray, within the trilinear interpolation bound
// elsewhere, its normals to second order, water against the box faces, misses.

#include "shellflow/preview_writer/water_surface.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "preview_fixture.hpp"

namespace shellflow::preview_writer {
namespace {

using namespace testing;
using writer_testing::SyntheticFluid;

// The march's step, as the renderer uses it (half a voxel).
constexpr double kStep = 0.5 * kWaterDx;
// Refinement stops at |φ| or a bracket of 1e-9 dx (water_surface.cpp); with |dφ/ds| ≥ 0.1
// on the rays below, the hit distance is that close to the trilinear φ's zero up to 1e-8 dx.
constexpr double kRefinement = 1e-8 * kWaterDx;

WaterSurface ball_surface(const SyntheticFluid& fluid) {
  return WaterSurface(fluid.fields()[0]);
}

TEST(WaterSurface, AlongAGridLineTheHitIsExact) {
  SyntheticFluid fluid;
  add_water_ball(fluid);
  const WaterSurface water = ball_surface(fluid);
  // The ray x = y = 0 runs along a line of nodes, where φ = |z| − r is linear between
  // nodes, so its trilinear interpolant is exact there: the hit is z = r, at distance 2.5.
  const WaterHit hit = water.first_hit({0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 1e9, kStep);
  ASSERT_TRUE(hit.hit());
  EXPECT_NEAR(hit.distance, 3.0 - kBallRadius, kRefinement);
  // By symmetry about the line the gradient is along z, up to round-off.
  EXPECT_NEAR(hit.normal.z(), 1.0, 1e-12);
  EXPECT_NEAR(hit.normal.x(), 0.0, 1e-12);
  EXPECT_NEAR(hit.normal.y(), 0.0, 1e-12);
}

TEST(WaterSurface, ObliqueHitsLieWithinTheTrilinearBoundAndNormalsAreSecondOrder) {
  SyntheticFluid fluid;
  add_water_ball(fluid);
  const WaterSurface water = ball_surface(fluid);
  const double h = kWaterDx;
  // Trilinear interpolation errs by at most h²/8 (|φ_xx| + |φ_yy| + |φ_zz|) over the cell;
  // for φ = |x| − r that sum is 2/ρ, ρ ≥ r − √3 h in the cells the surface crosses. Where
  // the trilinear φ is 0 the true φ = |p| − r is within that bound.
  const double position_bound = h * h / (4.0 * (kBallRadius - std::sqrt(3.0) * h));
  // The normal: central differences (error h²/6 |φ'''|) interpolated trilinearly (error
  // h²/8 Σ|∂²∇φ|), with third derivatives of |x| at most 3/ρ² per entry: in all about
  // √3 (1/2 + 9/8) h²/ρ² ≈ 0.024 here: an O(h²) bound, not an estimate (the rays below
  // see about a twentieth of it).
  const double rho = kBallRadius - std::sqrt(3.0) * h;
  const double normal_bound = std::sqrt(3.0) * (0.5 + 9.0 / 8.0) * h * h / (rho * rho);

  const Eigen::Vector3d eye(0.13, 0.21, 3.0);
  double worst_position = 0.0;
  double worst_normal = 0.0;
  int hits = 0;
  for (int a = -6; a <= 6; ++a)
    for (int b = -6; b <= 6; ++b) {
      // Aim at points of the ball's front half, up to 70° from the view axis.
      const double theta = 70.0 * M_PI / 180.0 * std::hypot(a, b) / 8.5;
      const double phi = std::atan2(b, a);
      const Eigen::Vector3d target =
          kBallRadius * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                        std::sin(theta) * std::sin(phi), std::cos(theta));
      const Eigen::Vector3d direction = (target - eye).normalized();
      const WaterHit hit = water.first_hit(eye, direction, 1e9, kStep);
      ASSERT_TRUE(hit.hit()) << a << ", " << b;
      ++hits;
      const Eigen::Vector3d p = eye + hit.distance * direction;
      worst_position = std::max(worst_position, std::abs(p.norm() - kBallRadius));
      worst_normal = std::max(worst_normal, (hit.normal - p.normalized()).norm());
      EXPECT_NEAR(hit.normal.norm(), 1.0, 1e-12);
    }
  EXPECT_EQ(hits, 169);
  EXPECT_LE(worst_position, position_bound);
  EXPECT_LE(worst_normal, normal_bound);
  // And the errors are there (no accidental exactness): a sizeable part of the bounds.
  EXPECT_GT(worst_position, 0.05 * position_bound);
  EXPECT_GT(worst_normal, 0.01 * normal_bound);
}

TEST(WaterSurface, MissesAndStopsAtTheSegmentsEnd) {
  SyntheticFluid fluid;
  add_water_ball(fluid);
  const WaterSurface water = ball_surface(fluid);
  // Passing 0.52 m from the centre, outside the ball (and through the band, φ ≥ 0.02).
  EXPECT_FALSE(water.first_hit({0.52, 0.0, 3.0}, {0.0, 0.0, -1.0}, 1e9, kStep).hit());
  // Missing the box altogether.
  EXPECT_FALSE(water.first_hit({2.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 1e9, kStep).hit());
  // A segment ending before the surface (a shell at z = 0.6 in front of it) sees no water.
  EXPECT_FALSE(water.first_hit({0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 2.4, kStep).hit());
  EXPECT_TRUE(water.first_hit({0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 2.6, kStep).hit());
}

TEST(WaterSurface, WaterAgainstTheBoxFaceIsHitOnTheFace) {
  // A pool filling the box below y = 0.3: a ray entering through the face x = -0.8 below
  // the surface meets water at the face, facing -x.
  SyntheticFluid fluid;
  auto& phi = fluid.add("phi", sdk::FieldView::Location::Node, Eigen::Vector3d::Constant(-0.8),
                        kWaterDx, {kWaterNodes, kWaterNodes, kWaterNodes}, 1);
  phi.fill(0, [](const Eigen::Vector3d& x) { return std::clamp(x.y() - 0.3, -0.12, 0.12); });
  const WaterSurface water(fluid.fields()[0]);
  const WaterHit side = water.first_hit({-3.0, 0.1, 0.05}, {1.0, 0.0, 0.0}, 1e9, kStep);
  ASSERT_TRUE(side.hit());
  EXPECT_NEAR(side.distance, 2.2, 1e-12);  // the face x = -0.8: 2.2 from x = -3
  EXPECT_EQ(side.normal, Eigen::Vector3d(-1.0, 0.0, 0.0));
  // From above, the flat surface y = 0.3 with normal +y (φ linear in y: exact).
  const WaterHit top = water.first_hit({0.1, 2.0, 0.05}, {0.0, -1.0, 0.0}, 1e9, kStep);
  ASSERT_TRUE(top.hit());
  EXPECT_NEAR(top.distance, 1.7, kRefinement);
  EXPECT_NEAR(top.normal.y(), 1.0, 1e-12);
}

TEST(WaterSurface, ACellCentredPoolIsHitInTheHalfCellStripAtTheWalls) {
  // A pool one cell deep on cell centres (the layout "cells" of grid_fluid: 40^3 cells of
  // kWaterDx filling [-0.8, 0.8]^3, origin the first centre): its water lies in the first
  // layer, φ = y − (floor + 0.75 dx). Seen from the side a quarter cell above the floor,
  // below the first centres, where φ continues constant to the wall: the ray meets water
  // at the face x = -0.8, facing -x. With the box of the samples alone it would pass
  // under them and see nothing.
  const double floor = -0.8, top = floor + 0.75 * kWaterDx;
  SyntheticFluid fluid;
  auto& phi = fluid.add("phi", sdk::FieldView::Location::Cell,
                        Eigen::Vector3d::Constant(-0.8 + 0.5 * kWaterDx), kWaterDx,
                        {kWaterNodes - 1, kWaterNodes - 1, kWaterNodes - 1}, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) { return x.y() - top; });
  const WaterSurface water(fluid.fields()[0]);
  const double strip = floor + 0.25 * kWaterDx;
  const WaterHit side = water.first_hit({-3.0, strip, 0.05}, {1.0, 0.0, 0.0}, 1e9, kStep);
  ASSERT_TRUE(side.hit());
  EXPECT_NEAR(side.distance, 2.2, 1e-12);  // the face x = -0.8: 2.2 from x = -3
  EXPECT_EQ(side.normal, Eigen::Vector3d(-1.0, 0.0, 0.0));
  // Along the wall's strip, from the far corner: water at once, at the face z = 0.8.
  const WaterHit along =
      water.first_hit({-0.8 + 0.25 * kWaterDx, strip, 3.0}, {0.0, 0.0, -1.0}, 1e9, kStep);
  ASSERT_TRUE(along.hit());
  EXPECT_NEAR(along.distance, 2.2, 1e-12);
  // From above, the top at floor + 0.75 dx (φ linear in y between the first two layers of
  // centres: exact), not at the first centres.
  const WaterHit from_above = water.first_hit({0.1, 2.0, 0.05}, {0.0, -1.0, 0.0}, 1e9, kStep);
  ASSERT_TRUE(from_above.hit());
  EXPECT_NEAR(from_above.distance, 2.0 - top, kRefinement);
  // Just above the water's top, along the same side: air.
  EXPECT_FALSE(
      water.first_hit({-3.0, top + 0.1 * kWaterDx, 0.05}, {1.0, 0.0, 0.0}, 1e9, kStep).hit());
}

TEST(WaterSurface, RejectsAVectorField) {
  SyntheticFluid fluid;
  fluid.add("phi", sdk::FieldView::Location::Node, Eigen::Vector3d::Zero(), 0.1, {4, 4, 4}, 3);
  EXPECT_THROW(WaterSurface{fluid.fields()[0]}, std::invalid_argument);
}

}  // namespace
}  // namespace shellflow::preview_writer
