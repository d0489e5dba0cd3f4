// vdb_writer: frames from a synthetic fluid, read back with the OpenVDB library.

#include "shellflow/vdb_writer/vdb_writer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "shellflow/sdk/error.hpp"
#include "synthetic_fluid.hpp"

namespace shellflow::vdb_writer {
namespace {

using writer_testing::SyntheticFluid;
using Location = sdk::FieldView::Location;

// Transforms: indexToWorld computes origin + dx * ijk in double; a few ulps of |x| ~ 1.
constexpr double kTransformTolerance = 1e-12;
// World-space trilinear lookup at a sample's position: the world→index map returns the
// integer index up to double round-off (~1e-15), so the weights are (1, 0) up to that and
// the float value comes back to float precision (2^-23 relative ≈ 1.2e-7; 1e-6 leaves room).
constexpr double kSamplerRelativeTolerance = 1e-6;

class VdbWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    openvdb::initialize();
    m_out = std::filesystem::temp_directory_path() /
            ("shellflow_vdb_writer_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(m_out);
    std::filesystem::create_directories(m_out);
  }
  void TearDown() override { std::filesystem::remove_all(m_out); }

  /// A smoke puff in a 12 x 10 x 8 box of cells, dx = 0.1 (not representable in binary):
  /// cell-centred density and temperature excess inside a sphere, zero outside; node
  /// velocity (a rotation plus an updraft) inside a smaller box, zero outside.
  void make_puff(SyntheticFluid& fluid) const {
    const Eigen::Vector3d corner(-0.6, 0.05, -1.0 / 3.0);
    const std::array<int, 3> cells{12, 10, 8};
    const Eigen::Vector3d centre = corner + m_dx * Eigen::Vector3d(6.0, 4.5, 4.0);
    auto puff = [=](const Eigen::Vector3d& x) {
      const double r2 = (x - centre).squaredNorm() / (0.35 * 0.35);
      return r2 < 1.0 ? (1.0 - r2) * (1.0 + x.x() / 7.0) : 0.0;
    };
    auto& density = fluid.add("density", Location::Cell,
                              corner + Eigen::Vector3d::Constant(0.5 * m_dx), m_dx, cells, 1);
    density.fill(0, puff);
    auto& temperature = fluid.add("temperature", Location::Cell,
                                  corner + Eigen::Vector3d::Constant(0.5 * m_dx), m_dx, cells, 1);
    temperature.fill(0, [&](const Eigen::Vector3d& x) { return 40.0 * puff(x); });
    auto& velocity = fluid.add("velocity", Location::Node, corner, m_dx,
                               {cells[0] + 1, cells[1] + 1, cells[2] + 1}, 3);
    const Eigen::Vector3d lo = corner + m_dx * Eigen::Vector3d(2, 2, 2);
    const Eigen::Vector3d hi = corner + m_dx * Eigen::Vector3d(9, 8, 6);
    auto inside = [=](const Eigen::Vector3d& x) {
      return (x.array() >= lo.array() - 1e-9).all() && (x.array() <= hi.array() + 1e-9).all();
    };
    velocity.fill(
        0, [=](const Eigen::Vector3d& x) { return inside(x) ? -(x.y() - centre.y()) : 0.0; });
    velocity.fill(
        1, [=](const Eigen::Vector3d& x) { return inside(x) ? (x.x() - centre.x()) + 0.3 : 0.0; });
    velocity.fill(2,
                  [=](const Eigen::Vector3d& x) { return inside(x) ? 0.1 * x.z() + 1e-3 : 0.0; });
  }

  VdbWriter make_writer(double tolerance, const std::string& velocity_name = "vel", int every = 1,
                        double level_set_half_width = 3.0) const {
    const nlohmann::json params = {{"folder", "volumes"},
                                   {"every", every},
                                   {"background_tolerance", tolerance},
                                   {"velocity_name", velocity_name},
                                   {"half_float", false},
                                   {"level_set_half_width", level_set_half_width}};
    return VdbWriter(params, sdk::Context{});
  }

  std::set<std::string> files_in(const std::filesystem::path& folder) const {
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      names.insert(entry.path().filename().string());
    return names;
  }

  std::map<std::string, openvdb::GridBase::Ptr> read_grids(
      const std::filesystem::path& file, openvdb::MetaMap::Ptr* metadata = nullptr) const {
    openvdb::io::File in(file.string());
    in.open();
    std::map<std::string, openvdb::GridBase::Ptr> grids;
    const openvdb::GridPtrVecPtr all =
        in.getGrids();  // named: a temporary would die before the loop
    for (const auto& grid : *all) grids[grid->getName()] = grid;
    if (metadata) *metadata = in.getMetadata();
    in.close();
    return grids;
  }

  std::filesystem::path m_out;
  double m_dx = 0.1;
};

void expect_transform(const openvdb::GridBase& grid, const SyntheticFluid::Field& field) {
  for (const auto& ijk :
       {openvdb::Coord(0, 0, 0), openvdb::Coord(3, 1, 2),
        openvdb::Coord(field.dims[0] - 1, field.dims[1] - 1, field.dims[2] - 1)}) {
    const openvdb::Vec3d world = grid.indexToWorld(ijk);
    const Eigen::Vector3d expected = field.position(ijk.x(), ijk.y(), ijk.z());
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(world[c], expected[c], kTransformTolerance) << grid.getName() << " " << ijk;
  }
  EXPECT_NEAR(grid.voxelSize()[0], field.dx, kTransformTolerance);
  EXPECT_TRUE(grid.transform().hasUniformScale());
}

/// Every sample reads back as float(value) exactly; active exactly where |value| > 0 (tolerance 0).
void expect_scalar_values(const openvdb::FloatGrid& grid, const SyntheticFluid::Field& field,
                          double tolerance) {
  auto accessor = grid.getConstAccessor();
  openvdb::Index64 expected_active = 0;
  for (int k = 0; k < field.dims[2]; ++k)
    for (int j = 0; j < field.dims[1]; ++j)
      for (int i = 0; i < field.dims[0]; ++i) {
        const double value = field.data[0][field.index(i, j, k)];
        const bool active = std::abs(static_cast<float>(value)) > static_cast<float>(tolerance);
        expected_active += active;
        const openvdb::Coord ijk(i, j, k);
        ASSERT_EQ(accessor.isValueOn(ijk), active) << grid.getName() << " " << ijk;
        // Exact: the only change is the double → float rounding.
        ASSERT_EQ(accessor.getValue(ijk), active ? static_cast<float>(value) : 0.0f)
            << grid.getName() << " " << ijk;
      }
  EXPECT_EQ(grid.activeVoxelCount(), expected_active);
  EXPECT_GT(expected_active, 0u);
  EXPECT_LT(expected_active, static_cast<openvdb::Index64>(field.data[0].size()));  // sparse
}

TEST_F(VdbWriterTest, WritesGridsWithBlenderNamesTransformsAndExactFloatValues) {
  SyntheticFluid fluid;
  make_puff(fluid);
  auto writer = make_writer(0.0);
  writer.begin({m_out, "plume", 24.0});
  writer.write_frame({7, 7.0 / 24.0, {}, &fluid});

  EXPECT_EQ(files_in(m_out / "volumes"),
            std::set<std::string>{"plume_0007.vdb"});  // no temporaries
  openvdb::MetaMap::Ptr metadata;
  auto grids = read_grids(m_out / "volumes" / "plume_0007.vdb", &metadata);
  ASSERT_EQ(grids.size(), 3u);
  ASSERT_TRUE(grids.count("density") && grids.count("temperature") && grids.count("vel"));
  EXPECT_EQ(metadata->metaValue<int32_t>("shellflow_frame"), 7);
  EXPECT_EQ(metadata->metaValue<std::string>("shellflow_scene"), "plume");

  const auto& density = fluid.field("density");
  const auto& temperature = fluid.field("temperature");
  const auto& velocity = fluid.field("velocity");

  auto density_grid = openvdb::gridPtrCast<openvdb::FloatGrid>(grids["density"]);
  auto temperature_grid = openvdb::gridPtrCast<openvdb::FloatGrid>(grids["temperature"]);
  auto velocity_grid = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grids["vel"]);
  ASSERT_TRUE(density_grid && temperature_grid && velocity_grid);
  EXPECT_EQ(density_grid->getGridClass(), openvdb::GRID_FOG_VOLUME);
  EXPECT_EQ(velocity_grid->getVectorType(), openvdb::VEC_CONTRAVARIANT_RELATIVE);
  EXPECT_EQ(density_grid->metaValue<std::string>("shellflow_sample_location"), "cell");
  EXPECT_EQ(velocity_grid->metaValue<std::string>("shellflow_sample_location"), "node");

  expect_transform(*density_grid, density);
  expect_transform(*temperature_grid, temperature);
  expect_transform(*velocity_grid, velocity);
  expect_scalar_values(*density_grid, density, 0.0);
  expect_scalar_values(*temperature_grid, temperature, 0.0);

  // Cell vs node positions in world space: a cell-centred sample (i,j,k) sits at
  // corner + dx (i + 1/2, ...), a node sample at corner + dx (i, ...).
  const Eigen::Vector3d corner(-0.6, 0.05, -1.0 / 3.0);
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> density_at(
      *density_grid);
  for (const auto& [i, j, k] : {std::array<int, 3>{6, 4, 4}, {5, 5, 3}, {7, 3, 4}}) {
    const Eigen::Vector3d x = corner + m_dx * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
    const double expected = density.data[0][density.index(i, j, k)];
    ASSERT_GT(expected, 0.1);
    EXPECT_NEAR(density_at.wsSample(openvdb::Vec3d(x.x(), x.y(), x.z())), expected,
                kSamplerRelativeTolerance * expected);
  }
  openvdb::tools::GridSampler<openvdb::Vec3SGrid, openvdb::tools::BoxSampler> velocity_at(
      *velocity_grid);
  {
    const int i = 5, j = 4, k = 3;
    const Eigen::Vector3d x = corner + m_dx * Eigen::Vector3d(i, j, k);
    const openvdb::Vec3s v = velocity_at.wsSample(openvdb::Vec3d(x.x(), x.y(), x.z()));
    for (int c = 0; c < 3; ++c) {
      const double expected = velocity.data[c][velocity.index(i, j, k)];
      EXPECT_NEAR(v[c], expected, kSamplerRelativeTolerance * (std::abs(expected) + 1.0));
    }
  }

  // Velocity: exact float values inside the box, inactive (background 0) outside.
  auto accessor = velocity_grid->getConstAccessor();
  openvdb::Index64 expected_active = 0;
  for (int k = 0; k < velocity.dims[2]; ++k)
    for (int j = 0; j < velocity.dims[1]; ++j)
      for (int i = 0; i < velocity.dims[0]; ++i) {
        const size_t s = velocity.index(i, j, k);
        const bool nonzero =
            velocity.data[0][s] != 0.0 || velocity.data[1][s] != 0.0 || velocity.data[2][s] != 0.0;
        expected_active += nonzero;
        const openvdb::Coord ijk(i, j, k);
        ASSERT_EQ(accessor.isValueOn(ijk), nonzero) << ijk;
        const openvdb::Vec3s v = accessor.getValue(ijk);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(v[c], static_cast<float>(velocity.data[c][s])) << ijk;
      }
  EXPECT_EQ(velocity_grid->activeVoxelCount(), expected_active);
  EXPECT_EQ(expected_active, 8u * 7u * 5u);  // nodes 2..9 x 2..8 x 2..6 of the box
}

/// The narrow band of a level set read back: every sample of `phi` is active exactly when
/// |float(φ)| < background, with value float(φ) (only the double → float rounding), and
/// inactive at −background in the water (φ < 0) or +background in the air otherwise.
/// `band` receives the number of active samples.
void expect_narrow_band(const openvdb::FloatGrid& grid, const SyntheticFluid::Field& phi,
                        openvdb::Index64& band) {
  const float background = grid.background();
  auto accessor = grid.getConstAccessor();
  band = 0;
  for (int k = 0; k < phi.dims[2]; ++k)
    for (int j = 0; j < phi.dims[1]; ++j)
      for (int i = 0; i < phi.dims[0]; ++i) {
        const float value = static_cast<float>(phi.data[0][phi.index(i, j, k)]);
        const bool active = std::abs(value) < background;
        band += active;
        const openvdb::Coord ijk(i, j, k);
        ASSERT_EQ(accessor.isValueOn(ijk), active) << ijk << " phi " << value;
        const float expected = active ? value : (value < 0.0f ? -background : background);
        ASSERT_EQ(accessor.getValue(ijk), expected) << ijk << " phi " << value;
      }
  EXPECT_EQ(grid.activeVoxelCount(), band);  // nothing active outside the field's box
  for (auto it = grid.cbeginValueOn(); it; ++it) {
    EXPECT_TRUE(it.isVoxelValue()) << "an active tile at " << it.getCoord();
    EXPECT_LT(std::abs(*it), background) << it.getCoord();
  }
}

TEST_F(VdbWriterTest, WaterLevelSetBecomesANarrowBandSurfaceGrid) {
  // A water drop: φ of a sphere of radius 0.3 (7.5 dx) on 30 x 28 x 26 nodes, dx = 0.04,
  // clamped to ±4 dx as a fluid clamps it beyond its band; velocity beside it, no density.
  SyntheticFluid fluid;
  const double dx = 0.04;
  const Eigen::Vector3d corner(-0.5, 0.1, -0.45);
  const Eigen::Vector3d centre = corner + dx * Eigen::Vector3d(14.3, 13.6, 12.2);
  const auto& phi =
      writer_testing::add_sphere_phi(fluid, corner, dx, {30, 28, 26}, centre, 0.3, 4.0 * dx);
  auto& velocity = fluid.add("velocity", Location::Node, corner, dx, {30, 28, 26}, 3);
  velocity.fill(1, [&](const Eigen::Vector3d& x) { return x.x() - centre.x(); });
  auto writer = make_writer(1e-4);  // level_set_half_width 3 voxels
  writer.begin({m_out, "drop", 24.0});
  writer.write_frame({3, 0.125, {}, &fluid});

  auto grids = read_grids(m_out / "volumes" / "drop_0003.vdb");
  ASSERT_EQ(grids.size(), 2u);
  ASSERT_TRUE(grids.count("surface") && grids.count("vel"));
  auto surface = openvdb::gridPtrCast<openvdb::FloatGrid>(grids["surface"]);
  ASSERT_TRUE(surface);
  EXPECT_EQ(surface->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(surface->metaValue<std::string>("shellflow_sample_location"), "node");
  // The fluid's clamp (4 dx) is wider than the writer's band: background = 3 dx.
  EXPECT_EQ(surface->background(), static_cast<float>(3.0 * dx));
  expect_transform(*surface, phi);

  openvdb::Index64 band = 0;
  expect_narrow_band(*surface, phi, band);
  // A shell of about 4π r² · 6 dx / dx³ ≈ 4200 samples out of 21840: sparse, not empty.
  EXPECT_GT(band, 2000u);
  EXPECT_LT(band, phi.data[0].size() / 3);

  auto accessor = surface->getConstAccessor();
  // The drop's centre (node (14, 14, 12), 0.4 dx from the centre) is deep inside.
  EXPECT_FALSE(accessor.isValueOn(openvdb::Coord(14, 14, 12)));
  EXPECT_EQ(accessor.getValue(openvdb::Coord(14, 14, 12)), -surface->background());
  // Far outside the band and outside the box: inactive air.
  for (const auto& ijk : {openvdb::Coord(0, 0, 0), openvdb::Coord(-40, -40, -40),
                          openvdb::Coord(29, 27, 25), openvdb::Coord(200, 5, 5)}) {
    EXPECT_FALSE(accessor.isValueOn(ijk)) << ijk;
    EXPECT_EQ(accessor.getValue(ijk), surface->background()) << ijk;
  }
  // A band node found through world space: the transform puts φ where the fluid had it.
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> phi_at(*surface);
  const int i = 14, j = 14, k = 20;  // 7.8 dx from the centre: 0.3 dx outside the sphere
  const double expected = phi.data[0][phi.index(i, j, k)];
  ASSERT_GT(expected, 0.0);
  ASSERT_LT(expected, 3.0 * dx);
  const Eigen::Vector3d x = phi.position(i, j, k);
  EXPECT_NEAR(phi_at.wsSample(openvdb::Vec3d(x.x(), x.y(), x.z())), expected,
              kSamplerRelativeTolerance * expected);
}

TEST_F(VdbWriterTest, PoolInteriorIsStoredAsInsideTilesAndANarrowFluidBandSetsTheBackground) {
  // A pool: water below y = 0.6 on 21 x 20 x 24 nodes of dx = 0.05 from y = 0 (surface on
  // node layer j = 12), φ = y − 0.6 clamped to ±2 dx — narrower than the writer's 4-voxel
  // band, so the background is the fluid's clamp, 2 dx, and the clamped plateau stays
  // inactive. The water reaches the box's walls, also the far wall x = 20 that ends inside
  // an 8^3 block (x = 16..23).
  SyntheticFluid fluid;
  const double dx = 0.05;
  auto& phi =
      fluid.add("phi", Location::Node, Eigen::Vector3d(-0.6, 0.0, -0.6), dx, {21, 20, 24}, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) { return std::clamp(x.y() - 0.6, -2 * dx, 2 * dx); });
  auto writer = make_writer(0.0, "vel", 1, 4.0);
  writer.begin({m_out, "pool", 24.0});
  writer.write_frame({0, 0.0, {}, &fluid});
  auto grids = read_grids(m_out / "volumes" / "pool_0000.vdb");
  ASSERT_EQ(grids.size(), 1u);
  auto surface = openvdb::gridPtrCast<openvdb::FloatGrid>(grids["surface"]);
  ASSERT_TRUE(surface);
  EXPECT_EQ(surface->background(), static_cast<float>(2.0 * dx));
  // The band is the node layers with |y − 0.6| < 2 dx: j = 11, 12, 13 (j = 10 and 14 sit
  // on the clamp, up to round-off that float rounding removes).
  openvdb::Index64 band = 0;
  expect_narrow_band(*surface, phi, band);
  EXPECT_EQ(band, 3u * 21u * 24u);
  // Sparse storage, by 8^3 blocks (3 along x, 3 along y, 3 along z): the block layer
  // j = 8..15 holds the band, 9 leaves; in the layer below (j = 0..7, all water) the 6
  // blocks wholly inside the box are inactive −background tiles and the 3 that the far
  // wall x = 20 cuts are leaves (water inside the box, air beyond it); the partial layer
  // above (j = 16..19, air) is background. 12 leaves.
  EXPECT_EQ(surface->tree().leafCount(), 12u);
  auto accessor = surface->getConstAccessor();
  EXPECT_EQ(accessor.getValue(openvdb::Coord(5, 2, 17)), -surface->background());
  EXPECT_FALSE(accessor.isValueOn(openvdb::Coord(5, 2, 17)));
  // Depth 2: a tile of the lower internal node (root 0, internal 1 and 2, leaf voxel 3).
  EXPECT_EQ(accessor.getValueDepth(openvdb::Coord(5, 2, 17)), 2);
  // Below the floor and beyond the far wall (outside the box, even in a block that holds
  // water): air.
  EXPECT_EQ(accessor.getValue(openvdb::Coord(5, -1, 5)), surface->background());
  EXPECT_EQ(accessor.getValue(openvdb::Coord(20, 2, 5)), -surface->background());
  EXPECT_EQ(accessor.getValue(openvdb::Coord(21, 2, 5)), surface->background());
}

TEST_F(VdbWriterTest, ACellCentredLevelSetIsWrittenOnTheCellCentres) {
  // grid_fluid's layout "cells": φ on the centres of 30 x 28 x 26 cells of dx = 0.04 whose
  // box starts at `corner` (origin the first centre, half a cell in), a pool whose surface
  // lies 2.3 cells above the floor, φ = y − surface clamped to ±4 dx. Voxel (i,j,k) is
  // cell (i,j,k): its centre at the cell's centre, its faces on the cell's faces, so the
  // voxels tile the domain box and the file says "cell".
  SyntheticFluid fluid;
  const double dx = 0.04;
  const Eigen::Vector3d corner(-0.5, 0.1, -0.45);
  const double surface_y = corner.y() + 2.3 * dx;
  const std::array<int, 3> cells{30, 28, 26};
  auto& phi = fluid.add("phi", Location::Cell, corner.array() + 0.5 * dx, dx, cells, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    return std::clamp(x.y() - surface_y, -4.0 * dx, 4.0 * dx);
  });
  auto writer = make_writer(0.0);  // level_set_half_width 3 voxels
  writer.begin({m_out, "pool", 24.0});
  writer.write_frame({0, 0.0, {}, &fluid});
  auto grids = read_grids(m_out / "volumes" / "pool_0000.vdb");
  auto surface = openvdb::gridPtrCast<openvdb::FloatGrid>(grids["surface"]);
  ASSERT_TRUE(surface);
  EXPECT_EQ(surface->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(surface->metaValue<std::string>("shellflow_sample_location"), "cell");
  expect_transform(*surface, phi);
  // The voxels' outer faces are the domain's walls.
  const openvdb::Vec3d lower = surface->indexToWorld(openvdb::Vec3d(-0.5, -0.5, -0.5));
  const openvdb::Vec3d upper =
      surface->indexToWorld(openvdb::Vec3d(cells[0] - 0.5, cells[1] - 0.5, cells[2] - 0.5));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(lower[a], corner[a], kTransformTolerance);
    EXPECT_NEAR(upper[a], corner[a] + dx * cells[a], kTransformTolerance);
  }
  openvdb::Index64 band = 0;
  expect_narrow_band(*surface, phi, band);
  // The centre layers within 3 dx of the surface (φ = (j − 1.8) dx): j = 0..4.
  EXPECT_EQ(band, 5u * 30u * 26u);
  // Through world space the zero is where the fluid's is: φ is linear in y between centre
  // layers 1 and 2, so OpenVDB's trilinear sample at the surface height is 0 up to float
  // rounding of values ~dx (2^-24 · 0.1 ≈ 6e-9; 1e-7 leaves room).
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> phi_at(*surface);
  EXPECT_NEAR(phi_at.wsSample(openvdb::Vec3d(0.013, surface_y, -0.2)), 0.0, 1e-7);
}

TEST_F(VdbWriterTest, ValuesWithinTheBackgroundToleranceBecomeInactive) {
  SyntheticFluid fluid;
  make_puff(fluid);
  // With tolerance 0.2 the puff's thin rim drops out: only |density| > 0.2 stays active.
  auto writer = make_writer(0.2, "velocity");
  writer.begin({m_out, "plume", 24.0});
  writer.write_frame({0, 0.0, {}, &fluid});
  auto grids = read_grids(m_out / "volumes" / "plume_0000.vdb");
  ASSERT_TRUE(grids.count("velocity"));  // the Blender name this time
  auto density_grid = openvdb::gridPtrCast<openvdb::FloatGrid>(grids["density"]);
  ASSERT_TRUE(density_grid);
  const auto& density = fluid.field("density");
  size_t rim = 0;  // samples in (0, 0.2]: active at tolerance 0, inactive here
  for (double v : density.data[0]) rim += v > 0.0 && v <= 0.2;
  ASSERT_GT(rim, 0u);
  expect_scalar_values(*density_grid, density, 0.2);
}

TEST_F(VdbWriterTest, EveryNthFrameAndNothingWithoutAFluid) {
  SyntheticFluid fluid;
  make_puff(fluid);
  auto writer = make_writer(0.0, "vel", 2);
  writer.begin({m_out, "plume", 24.0});
  for (int frame = 0; frame < 5; ++frame) writer.write_frame({frame, frame / 24.0, {}, &fluid});
  writer.write_frame({6, 0.25, {}, nullptr});  // a solids-only frame: no volume to write
  EXPECT_EQ(files_in(m_out / "volumes"),
            (std::set<std::string>{"plume_0000.vdb", "plume_0002.vdb", "plume_0004.vdb"}));
}

TEST_F(VdbWriterTest, MalformedFieldIsAnErrorAndLeavesNoFile) {
  SyntheticFluid fluid;
  fluid.add("strain", Location::Cell, Eigen::Vector3d::Zero(), 0.1, {4, 4, 4}, 2);
  auto writer = make_writer(0.0);
  writer.begin({m_out, "bad", 24.0});
  EXPECT_THROW(writer.write_frame({0, 0.0, {}, &fluid}), Error);
  EXPECT_TRUE(files_in(m_out / "volumes").empty());
}

TEST(VdbWriterParams, RejectsWhatTheSchemaCannotCheck) {
  const nlohmann::json empty_folder = {{"folder", ""},
                                       {"every", 1},
                                       {"background_tolerance", 0.0},
                                       {"velocity_name", "vel"},
                                       {"half_float", false}};
  try {
    VdbWriter writer(empty_folder, sdk::Context{});
    FAIL() << "an empty folder was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/folder");
  }
  nlohmann::json narrow_band = empty_folder;
  narrow_band["folder"] = "volumes";
  narrow_band["level_set_half_width"] = 0.5;
  try {
    VdbWriter writer(narrow_band, sdk::Context{});
    FAIL() << "a level set band narrower than a voxel was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/level_set_half_width");
  }
  EXPECT_EQ(vdb_file_name("plume", 12), "plume_0012.vdb");
  EXPECT_EQ(vdb_file_name("plume", 12345), "plume_12345.vdb");
}

}  // namespace
}  // namespace shellflow::vdb_writer
