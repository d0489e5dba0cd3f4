// particle_files: particle sets written as PLY point clouds (read back with a small
// independent reader) and as OpenVDB point grids (read back with OpenVDB), every
// attribute compared.

#include "shellflow/liquid_writer/particle_files.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointCount.h>
#include <openvdb/points/PointDataGrid.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "ply_reader.hpp"

namespace shellflow::liquid_writer {
namespace {

/// A particle set owned by the test: particle i has radius 1e-3 (i + 1) (a unique key).
struct Particles {
  std::array<std::vector<double>, 3> x, u;
  std::vector<double> r;
  Particles(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        x[a].push_back(0.5 + 0.45 * unit(rng));
        u[a].push_back(3.0 * unit(rng));
      }
      r.push_back(1e-3 * (i + 1));
    }
  }
  sdk::ParticleView view(const std::string& name) const {
    sdk::ParticleView v;
    v.name = name;
    v.count = static_cast<std::int64_t>(r.size());
    for (int a = 0; a < 3; ++a) {
      v.position[a] = x[a].data();
      v.velocity[a] = u[a].data();
    }
    v.radius = r.data();
    return v;
  }
};

TEST(ParticleFiles, PlyHoldsPositionsVelocitiesAndRadiiAsFloats) {
  const Particles p(57, 1);
  std::stringstream out;
  write_particle_ply(out, p.view("spray"), 7, 0.25);
  const testing::PlyFile ply = testing::read_ply(out);
  ASSERT_EQ(ply.vertex_count, 57u);
  EXPECT_EQ(ply.properties, (std::vector<std::string>{"x", "y", "z", "vx", "vy", "vz", "radius"}));
  EXPECT_TRUE(ply.faces.empty());
  // Each value is the double rounded to float, bit for bit.
  for (size_t i = 0; i < 57; ++i) {
    EXPECT_EQ(ply.value(i, "x"), static_cast<float>(p.x[0][i]));
    EXPECT_EQ(ply.value(i, "y"), static_cast<float>(p.x[1][i]));
    EXPECT_EQ(ply.value(i, "z"), static_cast<float>(p.x[2][i]));
    EXPECT_EQ(ply.value(i, "vx"), static_cast<float>(p.u[0][i]));
    EXPECT_EQ(ply.value(i, "vy"), static_cast<float>(p.u[1][i]));
    EXPECT_EQ(ply.value(i, "vz"), static_cast<float>(p.u[2][i]));
    EXPECT_EQ(ply.value(i, "radius"), static_cast<float>(p.r[i]));
  }
}

TEST(ParticleFiles, PlyOfAnEmptySetIsAValidEmptyCloud) {
  sdk::ParticleView empty;
  empty.name = "spray";
  std::stringstream out;
  write_particle_ply(out, empty, 0, 0.0);
  const testing::PlyFile ply = testing::read_ply(out);
  EXPECT_EQ(ply.vertex_count, 0u);
}

TEST(ParticleFiles, VdbPointGridsReadBackWithPositionVelocityAndRadius) {
  openvdb::initialize();
  const auto file = std::filesystem::temp_directory_path() /
                    ("shellflow_particle_files_" + std::to_string(::getpid()) + ".vdb");
  const Particles spray(300, 2), water(5, 3);
  sdk::ParticleView empty;
  empty.name = "air_particles";
  const std::vector<sdk::ParticleView> sets{spray.view("spray"), water.view("water_particles"),
                                            empty};
  const double voxel = 1.0 / 32;
  write_particle_vdb(file, sets, voxel, {"scene", 3, 0.125});

  openvdb::io::File in(file.string());
  in.open();
  EXPECT_EQ(in.getMetadata()->metaValue<int>("shellflow_frame"), 3);
  std::map<std::string, const Particles*> expected{{"spray", &spray}, {"water_particles", &water}};
  int grids = 0;
  for (auto it = in.beginName(); it != in.endName(); ++it, ++grids) {
    const auto grid = openvdb::gridPtrCast<openvdb::points::PointDataGrid>(in.readGrid(*it));
    ASSERT_TRUE(grid) << *it << " is not a point grid";
    const auto& tree = grid->tree();
    if (*it == "air_particles") {
      EXPECT_EQ(openvdb::points::pointCount(tree), 0u);
      continue;
    }
    const Particles& p = *expected.at(*it);
    ASSERT_EQ(openvdb::points::pointCount(tree), p.r.size()) << *it;
    std::vector<int> seen(p.r.size(), 0);
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
      openvdb::points::AttributeHandle<openvdb::Vec3f> position(leaf->constAttributeArray("P"));
      openvdb::points::AttributeHandle<openvdb::Vec3f> velocity(leaf->constAttributeArray("v"));
      openvdb::points::AttributeHandle<float> radius(leaf->constAttributeArray("pscale"));
      for (auto index = leaf->beginIndexOn(); index; ++index) {
        // Radius 1e-3 (i + 1) names the particle.
        const int i = static_cast<int>(std::lround(radius.get(*index) / 1e-3)) - 1;
        ASSERT_GE(i, 0);
        ASSERT_LT(i, static_cast<int>(p.r.size()));
        ++seen[i];
        EXPECT_EQ(radius.get(*index), static_cast<float>(p.r[i]));
        const openvdb::Vec3d world = grid->transform().indexToWorld(
            index.getCoord().asVec3d() + openvdb::Vec3d(position.get(*index)));
        // Voxel-relative float offsets in [-1/2, 1/2]: half an ulp, 2^-26 voxel ≈ 5e-10 m.
        constexpr double kPositionTolerance = 2e-9;
        const openvdb::Vec3f v = velocity.get(*index);
        for (int a = 0; a < 3; ++a) {
          EXPECT_NEAR(world[a], p.x[a][i], kPositionTolerance);
          EXPECT_EQ(v[a], static_cast<float>(p.u[a][i]));
        }
      }
    }
    for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << *it << " particle " << i;
  }
  EXPECT_EQ(grids, 3);
  in.close();
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace shellflow::liquid_writer
