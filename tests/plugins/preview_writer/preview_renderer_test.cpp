// preview_writer: the renderer against known answers — Beer–Lambert through a slab, the
// march's step error bound, shells hiding and attenuated by smoke, shells-only frames, the
// water ball shaded and composited with shells by depth.

#include "shellflow/preview_writer/preview_renderer.hpp"

#include <gtest/gtest.h>

#include <cmath>
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
