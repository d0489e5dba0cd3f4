// preview_writer: the renderer against known answers — Beer–Lambert through a slab, the
// march's step error bound, shells hiding and attenuated by smoke, shells-only frames, the
// water ball shaded and composited with shells by depth; the domain's walls behind them.

#include "shellflow/preview_writer/preview_renderer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "preview_fixture.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/preview_writer/smoke_volume.hpp"
#include "shellflow/preview_writer/water_surface.hpp"

namespace shellflow::preview_writer {
namespace {

using namespace testing;
using writer_testing::SyntheticFluid;

/// 255 · (the colour the renderer should produce), for comparison with the bytes.
Eigen::Vector3d levels(const Eigen::Vector3d& colour) {
  return 255.0 * colour;
}

void expect_pixel(const RgbImage& image, int x, int y, const Eigen::Vector3d& expected_colour,
                  double tolerance_levels) {
  const Eigen::Vector3i p = image.at(x, y);
  const Eigen::Vector3d e = levels(expected_colour);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(p[c], e[c], tolerance_levels) << "pixel (" << x << ", " << y << ") channel " << c;
}

TEST(SmokeVolume, OpticalDepthOfTheSlabIsExactForAlignedStepsAndWithinTheMidpointBound) {
  SyntheticFluid fluid;
  add_slab(fluid);
  const SmokeVolume volume(fluid.fields()[0]);
  EXPECT_NEAR(volume.lower().z(), -0.5, 1e-15);
  EXPECT_NEAR(volume.upper().z(), 0.5, 1e-15);
  const Eigen::Vector3d origin(0.01, -0.02, 3.0);
  const Eigen::Vector3d down(0.0, 0.0, -1.0);
  const double exact = kRho * kSlabLength;
  // h = dx/2 from the box face: every step ends on a sample plane, the interpolant is
  // linear within each step, the midpoint rule is exact; only round-off remains
  // (~40 steps of |ρ h| ~ 0.05 with relative error 1e-16).
  EXPECT_NEAR(volume.optical_depth(origin, down, 0.0, 1e9, 0.5 * kDx, 1e9), exact, 1e-12);
  // Other steps: 4 kinks (slope jump kRho/dx each), each within one step erring by at most
  // kRho/dx · h²/8 (smoke_volume.hpp) — and the error is really there for these h.
  for (double h_voxels : {0.37, 0.8, 1.3}) {
    const double h = h_voxels * kDx;
    const double bound = 4.0 * (kRho / kDx) * h * h / 8.0;
    const double depth = volume.optical_depth(origin, down, 0.0, 1e9, h, 1e9);
    EXPECT_LE(std::abs(depth - exact), bound + 1e-12) << "h = " << h_voxels << " dx";
    EXPECT_GT(std::abs(depth - exact), 1e-3 * bound) << "h = " << h_voxels << " dx: no step error?";
  }
  // Stopping at the plane z = 0 (a shell there): half the slab, ρ · (0.225 + 0.025).
  EXPECT_NEAR(volume.optical_depth(origin, down, 0.0, 3.0, 0.5 * kDx, 1e9), 0.5 * exact, 1e-12);
  // Nothing outside the box.
  EXPECT_EQ(volume.density(Eigen::Vector3d(0.0, 0.0, 0.51)), 0.0);
  EXPECT_EQ(volume.density(Eigen::Vector3d(0.0, 0.0, 0.0)), kRho);
}

TEST(PreviewRenderer, SlabTransmittanceIsBeerLambert) {
  SyntheticFluid fluid;
  add_slab(fluid);
  const PreviewSettings s = slab_settings();
  const PreviewRenderer renderer(s);
  const RgbImage image = renderer.render({0, 0.0, {}, &fluid});
  ASSERT_EQ(image.width, 31);
  ASSERT_EQ(image.height, 21);

  // Along the axis: T = exp(-σ ρ L); aligned steps, so only 8-bit quantisation.
  const double T = std::exp(-kSigma * kRho * kSlabLength);
  expect_pixel(image, kCentreX, kCentreY, T * s.background_color, kQuantisation);

  // An oblique pixel: the path through the slab is L / |d_z|; the ray's steps no longer
  // end on the sample planes, so the midpoint bound applies with the slope jump seen
  // along the ray, kRho |d_z| / dx: |Δ(∫ρ)| ≤ 4 · kRho |d_z| / dx · h² / 8.
  const Ray ray = renderer.camera().pixel_ray(25, 10);  // leaves the slab at x ≈ 0.84 < 0.9
  const double dz = std::abs(ray.direction.z());
  const double T_oblique = std::exp(-kSigma * kRho * kSlabLength / dz);
  const double h = s.step_voxels * kDx;
  const double march_bound = kSigma * 4.0 * kRho * dz / kDx * h * h / 8.0;  // on σ∫ρ
  const double level_bound = 255.0 * T_oblique * march_bound;  // |ΔT| ≤ T |Δ(σ∫ρ)| (first order)
  expect_pixel(image, 25, 10, T_oblique * s.background_color, kQuantisation + level_bound);
  // The oblique path is 3 % longer: 2.6 levels darker, more than the tolerance above, so
  // the check sees the path length.
  EXPECT_LT(255.0 * T_oblique, 255.0 * T - 2.0);

  // A corner ray misses the volume (|x| > 0.9 already at the front face): background.
  expect_pixel(image, 0, 0, s.background_color, kQuantisation);
}

TEST(PreviewRenderer, SmokeColourFillsWhatTheSmokeAbsorbs) {
  SyntheticFluid fluid;
  add_slab(fluid);
  PreviewSettings s = slab_settings();
  s.smoke_color = {0.9, 0.3, 0.6};
  s.background_color = {0.0, 0.2, 0.1};
  const RgbImage image = PreviewRenderer(s).render({0, 0.0, {}, &fluid});
  const double T = std::exp(-kSigma * kRho * kSlabLength);
  expect_pixel(image, kCentreX, kCentreY, s.smoke_color * (1.0 - T) + T * s.background_color,
               kQuantisation);
}

TEST(PreviewRenderer, ShellInFrontHidesTheSmoke) {
  SyntheticFluid fluid;
  add_slab(fluid);
  const PreviewSettings s = slab_settings();
  const std::vector<sdk::ShellSurface> shells{square_shell(1.0, 0.1)};
  const PreviewRenderer renderer(s);
  const RgbImage image = renderer.render({0, 0.0, shells, &fluid});
  // Facing the camera, |n·d| = 1: the full shell colour, no smoke at all.
  expect_pixel(image, kCentreX, kCentreY, s.shell_color, kQuantisation);
  // Beside the square the ray reaches the smoke: darker than the background there.
  const Eigen::Vector3i beside = image.at(19, kCentreY);
  EXPECT_LT(beside[0], 255 * s.background_color[0] - 100);
}

TEST(PreviewRenderer, SmokeInFrontOfAShellDimsItAndStopsAtIt) {
  SyntheticFluid fluid;
  add_slab(fluid);
  const PreviewSettings s = slab_settings();
  const PreviewRenderer renderer(s);
  // Shell behind the volume: the whole slab in front, pixel = T · shell colour.
  const std::vector<sdk::ShellSurface> behind{square_shell(-1.0, 0.2)};
  const double T = std::exp(-kSigma * kRho * kSlabLength);
  expect_pixel(renderer.render({0, 0.0, behind, &fluid}), kCentreX, kCentreY, T * s.shell_color,
               kQuantisation);
  // Shell in the middle of the slab (z = 0): only the half in front counts, ρ L / 2
  // (the plane z = 0 is a step end, so again exact up to quantisation).
  const std::vector<sdk::ShellSurface> inside{square_shell(0.0, 0.2)};
  const double T_half = std::exp(-kSigma * kRho * 0.5 * kSlabLength);
  expect_pixel(renderer.render({0, 0.0, inside, &fluid}), kCentreX, kCentreY,
               T_half * s.shell_color, kQuantisation);
}

TEST(PreviewRenderer, ShellsOnlyFrameRendersShadedShells) {
  const auto mesh = geometry::make_sphere(0.5, 3);
  sdk::ShellSurface sphere;
  sphere.name = "ball/surface";
  sphere.positions = mesh.positions;
  sphere.velocities = sdk::Positions::Zero(mesh.positions.rows(), 3);
  sphere.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  sphere.surface_density = Eigen::VectorXd::Ones(mesh.triangles.rows());
  const std::vector<sdk::ShellSurface> shells{sphere};
  const PreviewSettings s = slab_settings();
  const RgbImage image = PreviewRenderer(s).render({0, 0.0, shells, nullptr});

  // Centre: a facet almost facing the camera. Level-3 icosphere facets are within ~5° of
  // the radial direction, so |n·d| ≥ cos 10° covers them with margin.
  const Eigen::Vector3i centre = image.at(kCentreX, kCentreY);
  const double lo = s.ambient + (1.0 - s.ambient) * std::cos(10.0 * M_PI / 180.0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(centre[c], std::lround(255 * s.shell_color[c]));
    EXPECT_GE(centre[c], std::floor(255 * s.shell_color[c] * lo));
  }
  // The headlight shade falls toward the silhouette (the sphere spans ~±0.5/2.5 rad).
  int rim_x = kCentreX;
  while (rim_x + 1 < image.width &&
         image.at(rim_x + 1, kCentreY) != image.at(image.width - 1, kCentreY))
    ++rim_x;
  ASSERT_GT(rim_x, kCentreX + 2);
  EXPECT_LT(image.at(rim_x, kCentreY)[0], centre[0]);
  // Corners: background.
  expect_pixel(image, 0, 0, s.background_color, kQuantisation);
  expect_pixel(image, image.width - 1, image.height - 1, s.background_color, kQuantisation);
}

/// The slab camera with a bluish water, distinct from the shell and the background.
PreviewSettings water_settings() {
  PreviewSettings s = slab_settings();
  s.water_color = {0.1, 0.3, 0.7};
  s.water_rim_color = {0.9, 0.9, 1.0};
  return s;
}

/// The water's shade where pixel (x, y)'s ray meets the ball (WaterSurface is tested on
/// its own, water_surface_test.cpp): what the renderer must put there with nothing in
/// front.
Eigen::Vector3d water_pixel(const PreviewRenderer& renderer, const SyntheticFluid& fluid, int x,
                            int y) {
  const Ray ray = renderer.camera().pixel_ray(x, y);
  const WaterSurface water(fluid.fields()[0]);
  const WaterHit hit = water.first_hit(ray.origin, ray.direction, 1e9, 0.5 * kWaterDx);
  EXPECT_TRUE(hit.hit()) << "pixel (" << x << ", " << y << ") misses the ball";
  return water_shade(renderer.settings(), hit.normal, ray.direction);
}

// The ball (radius 0.5 at 3 m) spans atan(0.5 / √(9 − 0.25)) = 0.169 in tan of the view
// angle; a pixel is 2 tan(15°)/21 = 0.0255 of it: pixels up to 6 from the centre see the
// ball, 7 and more pass it.
constexpr int kBallPixels = 6;

TEST(PreviewRenderer, WaterBallIsShadedWaterOnTheBackground) {
  SyntheticFluid fluid;
  add_water_ball(fluid);
  const PreviewSettings s = water_settings();
  const PreviewRenderer renderer(s);
  const RgbImage image = renderer.render({0, 0.0, {}, &fluid});
  // The centre pixel looks along the axis at the ball's pole: normal = view direction
  // (water_surface_test), cos θ = 1, F = F0 = 0.02: (1 − F0) · water colour + F0 · rim.
  EXPECT_NEAR(water_fresnel(1.0), 0.02, 1e-15);
  expect_pixel(image, kCentreX, kCentreY, 0.98 * s.water_color + 0.02 * s.water_rim_color,
               kQuantisation);
  // Across the ball: the water's shade of each ray's hit, bluish.
  for (int dx = -kBallPixels; dx <= kBallPixels; ++dx) {
    expect_pixel(image, kCentreX + dx, kCentreY,
                 water_pixel(renderer, fluid, kCentreX + dx, kCentreY), kQuantisation);
    const Eigen::Vector3i p = image.at(kCentreX + dx, kCentreY);
    EXPECT_GT(p[2], p[0] + 60) << "pixel " << kCentreX + dx << " is not water-blue";
  }
  // Beside the ball and in the corners: the background.
  for (int x : {kCentreX - kBallPixels - 1, kCentreX + kBallPixels + 1, 0, image.width - 1})
    expect_pixel(image, x, kCentreY, s.background_color, kQuantisation);
  expect_pixel(image, kCentreX, kCentreY - kBallPixels - 1, s.background_color, kQuantisation);
  expect_pixel(image, 0, 0, s.background_color, kQuantisation);
}

TEST(PreviewRenderer, ACellCentredPoolShowsItsWaterBelowTheFirstCentres) {
  // A pool one cell deep on cell centres (grid_fluid's layout "cells": 40^3 cells of
  // kWaterDx filling [-0.8, 0.8]^3), φ = y − (floor + 0.75 dx), seen from the side with the
  // eye a quarter cell above the floor, below the first centres. The centre pixel's ray
  // meets the water on the near face z = 0.8, head on: (1 − F0) water + F0 rim, as the
  // ball's pole. The pixel above passes 0.056 m higher at that face, over the water's top
  // (0.03 above the floor): the background.
  const double floor = -0.8;
  SyntheticFluid fluid;
  auto& phi = fluid.add("phi", sdk::FieldView::Location::Cell,
                        Eigen::Vector3d::Constant(-0.8 + 0.5 * kWaterDx), kWaterDx,
                        {kWaterNodes - 1, kWaterNodes - 1, kWaterNodes - 1}, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) { return x.y() - (floor + 0.75 * kWaterDx); });
  PreviewSettings s = water_settings();
  s.camera_position = {0.0, floor + 0.25 * kWaterDx, 3.0};
  s.look_at = {0.0, floor + 0.25 * kWaterDx, 0.0};
  const PreviewRenderer renderer(s);
  const RgbImage image = renderer.render({0, 0.0, {}, &fluid});
  expect_pixel(image, kCentreX, kCentreY, 0.98 * s.water_color + 0.02 * s.water_rim_color,
               kQuantisation);
  expect_pixel(image, kCentreX, kCentreY - 1, s.background_color, kQuantisation);
}

TEST(PreviewRenderer, ShellInFrontHidesTheWater) {
  SyntheticFluid fluid;
  add_water_ball(fluid);
  const PreviewSettings s = water_settings();
  const PreviewRenderer renderer(s);
  // A plate of half-side 0.1 at z = 1, 2 m from the eye: it covers tan 0.05, the pixels
  // within 1 of the centre; the water is behind it there and must not show.
  const std::vector<sdk::ShellSurface> shells{square_shell(1.0, 0.1)};
  const RgbImage image = renderer.render({0, 0.0, shells, &fluid});
  for (int dx = -1; dx <= 1; ++dx) {
    const Ray ray = renderer.camera().pixel_ray(kCentreX + dx, kCentreY);
    const double lambert = std::abs(ray.direction.z());  // the plate's normal is ±z
    expect_pixel(image, kCentreX + dx, kCentreY,
                 s.shell_color * (s.ambient + (1.0 - s.ambient) * lambert), kQuantisation);
  }
  // Beside the plate (3 pixels out: x = 0.15 at the plate) the ball shows as before.
  expect_pixel(image, kCentreX + 3, kCentreY, water_pixel(renderer, fluid, kCentreX + 3, kCentreY),
               kQuantisation);
}

TEST(PreviewRenderer, WaterInFrontHidesTheShellBehindIt) {
  SyntheticFluid fluid;
  add_water_ball(fluid);
  const PreviewSettings s = water_settings();
  const PreviewRenderer renderer(s);
  // A plate of half-side 0.75 at z = -0.7, behind the ball (and outside its band): the
  // ball in front of it shows, the plate only around the ball.
  const std::vector<sdk::ShellSurface> shells{square_shell(-0.7, 0.75)};
  const RgbImage image = renderer.render({0, 0.0, shells, &fluid});
  expect_pixel(image, kCentreX, kCentreY, 0.98 * s.water_color + 0.02 * s.water_rim_color,
               kQuantisation);
  expect_pixel(image, kCentreX + 4, kCentreY, water_pixel(renderer, fluid, kCentreX + 4, kCentreY),
               kQuantisation);
  // 7 pixels out the ray passes the ball and meets the plate at x = 3.7 · 0.179 = 0.66.
  const Ray ray = renderer.camera().pixel_ray(kCentreX + kBallPixels + 1, kCentreY);
  const double lambert = std::abs(ray.direction.z());
  expect_pixel(image, kCentreX + kBallPixels + 1, kCentreY,
               s.shell_color * (s.ambient + (1.0 - s.ambient) * lambert), kQuantisation);
}

TEST(PreviewRenderer, EmptyFrameIsBackground) {
  const PreviewSettings s = slab_settings();
  const RgbImage image = PreviewRenderer(s).render({0, 0.0, {}, nullptr});
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      expect_pixel(image, x, y, s.background_color, kQuantisation);
}

}  // namespace
}  // namespace shellflow::preview_writer

namespace shellflow::preview_writer {
namespace {

using namespace testing;
using writer_testing::SyntheticFluid;

TEST(PreviewRenderer, WaterTouchingAShellFromBehindDoesNotShowThroughIt) {
  // Water below a plate at z = 0.5, between node planes z = 0.48 (φ = −0.04: water) and
  // 0.52 (φ = +0.01: air on the camera's side). Plain trilinear φ puts the surface at
  // z = 0.512, in front of the plate; seen as the simulation sees it (§4.4.1: a point
  // above the plate uses only the nodes above it) the plate hides the water.
  SyntheticFluid fluid;
  auto& phi = fluid.add("phi", sdk::FieldView::Location::Node, Eigen::Vector3d::Constant(-0.8),
                        kWaterDx, {kWaterNodes, kWaterNodes, kWaterNodes}, 1);
  phi.fill(0, [](const Eigen::Vector3d& x) { return x.z() < 0.5 ? x.z() - 0.52 : x.z() - 0.51; });
  const PreviewSettings s = water_settings();
  const PreviewRenderer renderer(s);
  // Not vacuous: without the plate the trilinear surface shows (water-blue).
  const Eigen::Vector3i bare = renderer.render({0, 0.0, {}, &fluid}).at(kCentreX, kCentreY);
  EXPECT_GT(bare[2], bare[0] + 60);
  const std::vector<sdk::ShellSurface> shells{square_shell(0.5, 0.3)};
  const RgbImage image = renderer.render({0, 0.0, shells, &fluid});
  expect_pixel(image, kCentreX, kCentreY, s.shell_color, kQuantisation);  // lambert 1
}

}  // namespace
}  // namespace shellflow::preview_writer

// The domain's walls (DomainWalls): drawn where the background was, the floor with its grid,
// open sides not at all, water and smoke in front of them.
namespace shellflow::preview_writer {
namespace {

using namespace testing;
using writer_testing::SyntheticFluid;

sdk::DomainView closed_box(const Eigen::Vector3d& lower, const Eigen::Vector3d& upper) {
  sdk::DomainView d;
  d.lower = lower;
  d.upper = upper;
  return d;  // every side a wall
}

/// Wall colours far apart and a black background, so each pixel says what it shows.
PreviewSettings wall_settings(PreviewSettings s) {
  s.background_color = {0.0, 0.0, 0.0};
  s.wall_colours.wall = {0.2, 0.2, 0.2};
  s.wall_colours.floor = {0.4, 0.4, 0.4};
  s.wall_colours.grid = {0.8, 0.8, 0.8};
  return s;
}

/// The side (2 axis + max_side) through which the ray leaves the box; -1 when it misses the
/// box. (The rays below have no zero component.)
int exit_side(const sdk::DomainView& box, const Ray& ray) {
  double s_in = -std::numeric_limits<double>::infinity();
  double s_out = std::numeric_limits<double>::infinity();
  int side = -1;
  for (int a = 0; a < 3; ++a) {
    const int max_side = ray.direction[a] > 0.0 ? 1 : 0;
    const double far =
        ((max_side ? box.upper[a] : box.lower[a]) - ray.origin[a]) / ray.direction[a];
    const double near =
        ((max_side ? box.lower[a] : box.upper[a]) - ray.origin[a]) / ray.direction[a];
    s_in = std::max(s_in, near);
    if (far < s_out) {
      s_out = far;
      side = 2 * a + max_side;
    }
  }
  return s_in <= s_out ? side : -1;
}

/// The least distance from the ray to any of the box's 12 edges, in pixel widths at that
/// distance: each edge sampled at 200 points (a different route from DomainWalls' closed
/// form; the samples lie 1e-2 m apart on the 2 m box below, under half a pixel width, so
/// the result is at most a quarter of a pixel too large).
double pixels_to_nearest_edge(const sdk::DomainView& box, const Camera& camera, const Ray& ray) {
  double nearest = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 3; ++c)
    for (int corner = 0; corner < 4; ++corner) {
      Eigen::Vector3d p = box.lower;
      const int a = (c + 1) % 3, b = (c + 2) % 3;
      if (corner & 1) p[a] = box.upper[a];
      if (corner & 2) p[b] = box.upper[b];
      for (int n = 0; n <= 200; ++n) {
        p[c] = box.lower[c] + (box.upper[c] - box.lower[c]) * n / 200.0;
        const double s = (p - ray.origin).dot(ray.direction);
        if (s <= 0.0) continue;
        const double miss = (ray.origin + s * ray.direction - p).norm();
        const double width = s * ray.direction.dot(camera.forward()) * camera.pixel_size();
        nearest = std::min(nearest, miss / width);
      }
    }
  return nearest;
}

TEST(DomainWalls, TheFloorIsTheSideGravityPointsIntoAndTheGridSpacingIsRound) {
  EXPECT_EQ(floor_side({0.0, -9.81, 0.0}), 2);  // y_min
  EXPECT_EQ(floor_side({0.0, 0.0, -9.81}), 4);  // z_min
  EXPECT_EQ(floor_side({0.0, 9.81, 0.0}), 3);   // y_max: gravity upwards
  EXPECT_EQ(floor_side({1.0, -3.0, 0.5}), 2);   // tilted: the nearest axis
  EXPECT_THROW(floor_side(Eigen::Vector3d::Zero()), std::invalid_argument);
  // 1, 2 or 5 × 10^k, the largest not above a tenth of the longer side: 10 to 25 squares.
  // Exact in binary up to round-off of log10/pow (1e-15 relative).
  EXPECT_NEAR(grid_spacing(0.5), 0.05, 1e-15);
  EXPECT_NEAR(grid_spacing(6.0), 0.5, 1e-15);
  EXPECT_NEAR(grid_spacing(4.0), 0.2, 1e-15);
  EXPECT_NEAR(grid_spacing(1.0), 0.1, 1e-15);
  EXPECT_NEAR(grid_spacing(2.4), 0.2, 1e-15);
}

TEST(PreviewRenderer, EmptySceneShowsTheFloorAndNothingThroughAnOpenSide) {
  // A 2 x 1 x 2 m box seen from above and in front; the camera sits inside its x range, so
  // the x_max side is seen from inside on the right. No water, no smoke: only walls.
  PreviewSettings s = wall_settings(PreviewSettings{});
  s.camera_position = {0.3, 1.6, 3.5};
  s.look_at = {0.0, 0.3, 0.0};
  s.vertical_fov_deg = 40.0;
  s.width = 181;
  s.height = 121;
  const PreviewRenderer renderer(s);
  sdk::DomainView walled = closed_box({-1.0, 0.0, -1.0}, {1.0, 1.0, 1.0});
  sdk::DomainView open = walled;
  open.sides[1] = sdk::DomainView::Side::Open;  // x_max
  SyntheticFluid walled_fluid, open_fluid;
  walled_fluid.set_domain(walled);
  open_fluid.set_domain(open);
  const RgbImage with_wall = renderer.render({0, 0.0, {}, &walled_fluid});
  const RgbImage without = renderer.render({0, 0.0, {}, &open_fluid});
  // Nothing at all without a domain (and the same renderer again with one: the walls kept
  // for one domain are not reused for another).
  SyntheticFluid no_domain;
  const RgbImage bare = renderer.render({0, 0.0, {}, &no_domain});
  EXPECT_TRUE(std::all_of(bare.rgb.begin(), bare.rgb.end(), [](auto b) { return b == 0; }));

  int floor_pixels = 0, open_pixels = 0, line_pixels = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const Ray ray = renderer.camera().pixel_ray(x, y);
      // Edge lines are a pixel wide (a tent of one pixel's radius): 2 pixels away, none.
      if (pixels_to_nearest_edge(walled, renderer.camera(), ray) < 2.0) continue;
      const int side = exit_side(walled, ray);
      if (side < 0) {
        // Past the box: nothing drawn.
        EXPECT_EQ(with_wall.at(x, y), Eigen::Vector3i(0, 0, 0)) << x << ", " << y;
      } else if (side == 1) {
        // Through the open side: the background, exactly; a wall there when it is one.
        ++open_pixels;
        EXPECT_EQ(without.at(x, y), Eigen::Vector3i(0, 0, 0)) << x << ", " << y;
        EXPECT_EQ(with_wall.at(x, y), Eigen::Vector3i(51, 51, 51)) << x << ", " << y;
      } else if (side == 2) {
        // Through the floor: floor colour mixed with some grid colour, never background;
        // the same whether x_max is open or not. Bounds: the two colours' levels, 102 and
        // 204 (round(255 · 0.4), round(255 · 0.8)).
        ++floor_pixels;
        const Eigen::Vector3i p = without.at(x, y);
        EXPECT_EQ(p, with_wall.at(x, y));
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(p[c], 102) << x << ", " << y;
          EXPECT_LE(p[c], 204) << x << ", " << y;
        }
        line_pixels += p[0] > 153 ? 1 : 0;  // past half way to the grid colour: on a line
      }
    }
  // Not vacuous: both sides fill a good part of the image.
  EXPECT_GT(open_pixels, 400);
  EXPECT_GT(floor_pixels, 2000);
  // The grid shows (0.2 m squares, 8 to 14 pixels apart here, sharp lines): some floor
  // pixels on its lines, most between them.
  EXPECT_GT(line_pixels, 20);
  EXPECT_LT(line_pixels, floor_pixels / 2);
}

TEST(PreviewRenderer, WaterOverTheFloorKeepsItsColourAndHidesTheEdgesBehindIt) {
  // The ball resting on the floor of a closed box (floor y = -0.5, the ball's bottom).
  SyntheticFluid fluid;
  add_water_ball(fluid);
  const sdk::DomainView box = closed_box({-0.8, -0.5, -0.8}, {0.8, 0.8, 0.8});
  SyntheticFluid boxed;
  const auto& ball = fluid.field("phi");
  boxed.add("phi", ball.location, ball.origin, ball.dx, ball.dims, 1).data[0] = ball.data[0];
  boxed.set_domain(box);
  const PreviewSettings s = wall_settings(water_settings());
  const PreviewRenderer renderer(s);
  const RgbImage plain = renderer.render({0, 0.0, {}, &fluid});
  const RgbImage image = renderer.render({0, 0.0, {}, &boxed});
  // Every pixel whose ray meets the water has the water's own shade, exactly as without
  // the walls: the walls are behind it, and no edge is drawn over it.
  const WaterSurface water(fluid.fields()[0]);
  int water_pixels = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const Ray ray = renderer.camera().pixel_ray(x, y);
      if (!water.first_hit(ray.origin, ray.direction, 1e9, 0.5 * kWaterDx).hit()) continue;
      ++water_pixels;
      EXPECT_EQ(image.at(x, y), plain.at(x, y)) << x << ", " << y;
    }
  EXPECT_GT(water_pixels, 100);  // the ball covers ~13 x 13 pixels
  // Not vacuous: the floor's back edge (y = -0.5, z = -0.8; tan 0.5/3.8 = 5.16 pixels
  // below the centre) passes behind the ball at (15, 15), where it would show.
  EXPECT_GT(renderer.walls(box)->pixel(kCentreX, kCentreY + 5).edge_alpha, 0.5);
  // Beside the ball the back wall shows instead of the background (7 pixels out the ray
  // meets z = -0.8 at x = 0.68, 1.2 pixel widths from the nearest edge): 51 = round(255 · 0.2).
  EXPECT_EQ(plain.at(kCentreX + kBallPixels + 1, kCentreY), Eigen::Vector3i(0, 0, 0));
  EXPECT_EQ(image.at(kCentreX + kBallPixels + 1, kCentreY), Eigen::Vector3i(51, 51, 51));
  // Readable: the water facing the camera is far from the floor's and walls' greys — its
  // blue exceeds its red by 0.98 (0.7 − 0.1) + 0.02 (1.0 − 0.9) = 0.59, 150.45 levels (less
  // one for the rounding of the two bytes), where the greys have none.
  const Eigen::Vector3i centre = image.at(kCentreX, kCentreY);
  EXPECT_GT(centre[2] - centre[0], 149);
}

TEST(PreviewRenderer, SmokeInFrontOfTheWallsAbsorbsThemAsTheBackground) {
  // The slab filling its closed box: the centre ray leaves through the back wall z = -0.5
  // after the whole slab, so the pixel is smoke (1 − T) + T · wall (black smoke: T · wall).
  SyntheticFluid fluid;
  add_slab(fluid);
  fluid.set_domain(closed_box({-0.9, -0.9, -0.5}, {0.9, 0.9, 0.5}));
  const PreviewSettings s = wall_settings(slab_settings());
  const RgbImage image = PreviewRenderer(s).render({0, 0.0, {}, &fluid});
  const double T = std::exp(-kSigma * kRho * kSlabLength);
  expect_pixel(image, kCentreX, kCentreY, T * s.wall_colours.wall, kQuantisation);
  // And with white smoke: the smoke's colour where it absorbs, the wall's where it does not.
  PreviewSettings white = s;
  white.smoke_color = {1.0, 1.0, 1.0};
  expect_pixel(PreviewRenderer(white).render({0, 0.0, {}, &fluid}), kCentreX, kCentreY,
               Eigen::Vector3d::Constant(1.0 - T) + T * s.wall_colours.wall, kQuantisation);
}

TEST(FloorShadow, ColumnsHoldingWaterOrSmokeShadeTheFloorBelowThem) {
  // The ball (radius 0.5, nodes 0.04 apart, φ clamped to ±0.12) over a floor at y_min: the
  // column through its centre holds water, s = 1; the column at x = 0.7 is 0.2 clear of it
  // (φ ≥ band), s = 0. At x = 0.5, between the columns at 0.48 (min φ = −0.02: 1/2 + 1/2,
  // s = 1) and 0.52 (min φ = 0.02: s = 0), bilinear: 1/2. Round-off only (1e-14).
  SyntheticFluid fluid;
  add_water_ball(fluid);
  FloorShadow water(2);
  water.add_water(fluid.fields()[0]);
  EXPECT_NEAR(water.at({0.0, -0.8, 0.0}), 1.0, 1e-14);
  EXPECT_NEAR(water.at({0.7, -0.8, 0.0}), 0.0, 1e-14);
  EXPECT_NEAR(water.at({0.5, -0.8, 0.0}), 0.5, 1e-14);
  EXPECT_EQ(water.at({0.9, -0.8, 0.0}), 0.0);  // outside the field's box
  // The slab's column along z (a floor at z_min, gravity along −z): all its 10 layers,
  // s = 1 − exp(−σ ρ L), the slab's absorption seen straight through.
  SyntheticFluid slab;
  add_slab(slab);
  FloorShadow smoke(4);
  smoke.add_smoke(slab.fields()[0], kSigma);
  const double T = std::exp(-kSigma * kRho * kSlabLength);
  EXPECT_NEAR(smoke.at({0.1, -0.3, -0.5}), 1.0 - T, 1e-14);
  EXPECT_EQ(smoke.at({1.0, 0.0, -0.5}), 0.0);  // outside the field's box
  // Two fields: the light that passes each, 1 − (1 − s_1)(1 − s_2).
  FloorShadow both(4);
  both.add_smoke(slab.fields()[0], kSigma);
  both.add_smoke(slab.fields()[0], kSigma);
  EXPECT_NEAR(both.at({0.1, -0.3, -0.5}), 1.0 - T * T, 1e-14);
}

TEST(PreviewRenderer, WaterInMidAirCastsItsShadowOnTheFloorBelowIt) {
  // The ball 0.3 m above the floor of a closed box (y = −0.8), seen from above and in
  // front: the near part of its shadow shows on the floor below it.
  SyntheticFluid boxed;
  add_water_ball(boxed);
  const sdk::DomainView box = closed_box({-0.8, -0.8, -0.8}, {0.8, 0.8, 0.8});
  boxed.set_domain(box);
  PreviewSettings s = wall_settings(water_settings());
  s.camera_position = {0.0, 1.0, 3.0};
  s.look_at = {0.0, -0.4, 0.0};
  s.vertical_fov_deg = 50.0;
  s.width = 61;
  s.height = 61;
  const PreviewRenderer renderer(s);
  const RgbImage image = renderer.render({0, 0.0, {}, &boxed});
  const auto walls = renderer.walls(box);
  FloorShadow shadow(2);
  shadow.add_water(boxed.fields()[0]);
  const WaterSurface water(boxed.fields()[0]);
  int full = 0, clear = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const WallPixel& wall = walls->pixel(x, y);
      if (!wall.floor || wall.edge_alpha > 0.0) continue;
      const Ray ray = renderer.camera().pixel_ray(x, y);
      if (water.first_hit(ray.origin, ray.direction, 1e9, 0.5 * kWaterDx).hit()) continue;
      // The floor's own colour (with its grid) times 1 − floor_shadow · s.
      const double sh = shadow.at(ray.origin + wall.distance * ray.direction);
      expect_pixel(image, x, y, (1.0 - s.floor_shadow * sh) * wall.colour, kQuantisation);
      full += sh == 1.0 ? 1 : 0;
      clear += sh == 0.0 ? 1 : 0;
    }
  EXPECT_GT(full, 20);    // not vacuous: the shadow is seen ...
  EXPECT_GT(clear, 200);  // ... and the lit floor around it
}

TEST(PreviewRenderer, WallsAreTracedOncePerDomainAndCanBeTurnedOff) {
  PreviewSettings s = wall_settings(slab_settings());
  const PreviewRenderer renderer(s);
  const sdk::DomainView box = closed_box({-0.9, -0.9, -0.5}, {0.9, 0.9, 0.5});
  const auto first = renderer.walls(box);
  EXPECT_EQ(renderer.walls(box), first);  // kept: the per-pixel work is done once
  sdk::DomainView other = box;
  other.sides[4] = sdk::DomainView::Side::Open;
  EXPECT_NE(renderer.walls(other), first);
  EXPECT_EQ(renderer.walls(other)->floor(), 2);  // y_min: down is −y by default
  s.down = {0.0, 0.0, -1.0};
  EXPECT_EQ(PreviewRenderer(s).walls(box)->floor(), 4);     // z_min
  EXPECT_EQ(PreviewRenderer(s).walls(other)->floor(), -1);  // z_min open: no floor
  // Turned off: the image is the one without a domain.
  SyntheticFluid fluid;
  add_slab(fluid);
  SyntheticFluid boxed;
  add_slab(boxed);
  boxed.set_domain(box);
  s.walls = false;
  const PreviewRenderer off(s);
  EXPECT_EQ(off.render({0, 0.0, {}, &boxed}).rgb, off.render({0, 0.0, {}, &fluid}).rgb);
}

}  // namespace
}  // namespace shellflow::preview_writer
