#pragma once
// Known scenes for the preview tests: a slab of constant smoke density seen along its
// normal, a ball of water (a sphere's level set), flat square shells, and the camera that
// looks straight through the slab and at the ball's centre.

#include <cmath>
#include <memory>

#include "shellflow/preview_writer/preview_renderer.hpp"
#include "shellflow/sdk/shell_surface.hpp"
#include "synthetic_fluid.hpp"

namespace shellflow::preview_writer::testing {

// The grid: 36 x 36 x 20 cells of dx = 0.05 filling [-0.9, 0.9]^2 x [-0.5, 0.5]; the slab
// is cell layers k = 5..14 (density kRho) across the whole x-y extent, zero elsewhere.
constexpr double kDx = 0.05;
constexpr int kCellsXY = 36;
constexpr int kCellsZ = 20;
constexpr int kSlabFirst = 5;
constexpr int kSlabLast = 14;
constexpr double kRho = 2.0;
constexpr double kSigma = 1.5;  // [1/m per unit density]
// The trilinear interpolant of the cell values ramps from 0 to kRho over one dx on each
// side (between the centres of layers 4/5 and 14/15), so its integral across the slab is
// kRho times the layer count times dx: the slab's optical thickness is that of L = 10 dx.
constexpr double kSlabLength = (kSlabLast - kSlabFirst + 1) * kDx;
// Half of one 8-bit level: round(255 c) is within 0.5 of 255 c (plus double round-off).
constexpr double kQuantisation = 0.5 + 1e-9;

inline void add_slab(writer_testing::SyntheticFluid& fluid) {
  auto& density = fluid.add("density", sdk::FieldView::Location::Cell,
                            Eigen::Vector3d(-0.9, -0.9, -0.5).array() + 0.5 * kDx, kDx,
                            {kCellsXY, kCellsXY, kCellsZ}, 1);
  for (int k = kSlabFirst; k <= kSlabLast; ++k)
    for (int j = 0; j < kCellsXY; ++j)
      for (int i = 0; i < kCellsXY; ++i) density.data[0][density.index(i, j, k)] = kRho;
}

// The ball of water: φ = |x| − kBallRadius on 41^3 nodes of kWaterDx filling [-0.8, 0.8]^3
// (the centre on node (20, 20, 20)), clamped to ±3 dx as a fluid clamps it beyond its band.
constexpr double kWaterDx = 0.04;
constexpr int kWaterNodes = 41;
constexpr double kBallRadius = 0.5;
constexpr double kWaterBand = 3.0 * kWaterDx;

inline void add_water_ball(writer_testing::SyntheticFluid& fluid) {
  writer_testing::add_sphere_phi(fluid, Eigen::Vector3d::Constant(-0.8), kWaterDx,
                                 {kWaterNodes, kWaterNodes, kWaterNodes}, Eigen::Vector3d::Zero(),
                                 kBallRadius, kWaterBand);
}

/// A square of side 2 half_side in the plane z = z0, normal ±z, as two triangles.
inline sdk::ShellSurface square_shell(double z0, double half_side) {
  sdk::ShellSurface s;
  s.name = "square/surface";
  s.positions.resize(4, 3);
  s.positions << -half_side, -half_side, z0,  //
      half_side, -half_side, z0,              //
      half_side, half_side, z0,               //
      -half_side, half_side, z0;
  s.velocities = sdk::Positions::Zero(4, 3);
  sdk::Triangles t(2, 3);
  t << 0, 1, 2, 0, 2, 3;
  s.triangles = std::make_shared<const sdk::Triangles>(t);
  s.surface_density = Eigen::VectorXd::Ones(2);
  return s;
}

/// Camera on the +z axis looking down -z; with an odd image size the centre pixel
/// (15, 10) looks exactly along -z. Black smoke in front of a three-level background,
/// so a pixel channel reads 255 · background · T.
inline PreviewSettings slab_settings() {
  PreviewSettings s;
  s.camera_position = {0.0, 0.0, 3.0};
  s.look_at = {0.0, 0.0, 0.0};
  s.up = {0.0, 1.0, 0.0};
  s.vertical_fov_deg = 30.0;
  s.width = 31;
  s.height = 21;
  s.absorption = kSigma;
  s.step_voxels = 0.5;
  s.smoke_color = {0.0, 0.0, 0.0};
  s.background_color = {1.0, 0.5, 0.25};
  s.shell_color = {0.8, 0.6, 0.4};
  s.ambient = 0.2;
  return s;
}
constexpr int kCentreX = 15;
constexpr int kCentreY = 10;

}  // namespace shellflow::preview_writer::testing
