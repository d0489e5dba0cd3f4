// liquid_writer: the writer's files for a water fluid test double (surface OBJ and PLY,
// particle PLY and VDB), read back; nothing for a fluid without a level set; parameters
// refused with the JSON path named.

#include "shellflow/liquid_writer/liquid_writer.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <tiny_obj_loader.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>

#include "mesh_checks.hpp"
#include "ply_reader.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::liquid_writer {
namespace {

using testing::NodeGrid;

/// A water fluid double: a sphere of water (R = 0.25, 16^3 unit box) moving at (1, 2, 3)
/// m/s, and a spray set of three drops. φ on the nodes, or with `cells` on the cell
/// centres (as grid_fluid's layout "cells" publishes it; the velocity stays on the nodes).
class WaterDouble final : public sdk::FluidSolver {
 public:
  explicit WaterDouble(bool water = true, bool cells = false)
      : m_phi(cells ? Eigen::Vector3d::Constant(0.5 / 16) : Eigen::Vector3d::Zero(), 1.0 / 16,
              cells ? std::array<int, 3>{16, 16, 16} : std::array<int, 3>{17, 17, 17}, 1),
        m_velocity(Eigen::Vector3d::Zero(), 1.0 / 16, {17, 17, 17}, 3),
        m_water(water) {
    if (cells) m_phi.location = sdk::FieldView::Location::Cell;
    m_phi.fill(0, [](const Eigen::Vector3d& x) {
      return (x - Eigen::Vector3d::Constant(0.5)).norm() - 0.25;
    });
    for (int a = 0; a < 3; ++a) m_velocity.fill(a, [a](const Eigen::Vector3d&) { return a + 1.0; });
  }
  double stable_dt(double) const override { return std::numeric_limits<double>::infinity(); }
  void advect(double, double, sdk::ShellSet, sdk::ShellSet) override {}
  void coupling_forces(double, sdk::ShellSet, std::span<sdk::TriangleVectors>) override {}
  void project(double, sdk::ShellSet, std::span<const sdk::Positions>) override {}
  void save(sdk::StateWriter&) const override {}
  void restore(sdk::StateReader&) override {}
  std::vector<sdk::FieldView> fields() const override {
    if (!m_water) return {m_velocity.view("velocity")};
    return {m_phi.view("phi"), m_velocity.view("velocity")};
  }
  std::vector<sdk::ParticleView> particles() const override {
    sdk::ParticleView spray;
    spray.name = "spray";
    spray.count = 3;
    for (int a = 0; a < 3; ++a) {
      spray.position[a] = m_drops[a].data();
      spray.velocity[a] = m_drops[a].data();
    }
    spray.radius = m_drops[0].data();
    return {spray};
  }

 private:
  NodeGrid m_phi, m_velocity;
  bool m_water = true;
  std::array<std::vector<double>, 3> m_drops{std::vector<double>{0.1, 0.2, 0.3},
                                             std::vector<double>{0.4, 0.5, 0.6},
                                             std::vector<double>{0.7, 0.8, 0.9}};
};

class LiquidWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    m_out = std::filesystem::temp_directory_path() /
            ("shellflow_liquid_writer_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(m_out);
    std::filesystem::create_directories(m_out);
  }
  void TearDown() override { std::filesystem::remove_all(m_out); }
  sdk::RunInfo run_info() const { return {m_out, "pool", 24.0}; }
  std::filesystem::path m_out;
};

TEST_F(LiquidWriterTest, WritesTheSurfaceAndTheSprayOfAWrittenFrame) {
  const WaterDouble fluid;
  LiquidWriter writer({{"every", 2}, {"particles", {"spray", "air_particles"}}}, {});
  writer.begin(run_info());
  writer.write_frame({3, 0.125, {}, &fluid});  // not a multiple of "every": nothing
  writer.write_frame({4, 0.25, {}, &fluid});
  const auto folder = m_out / "liquid";
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    names.insert(entry.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"pool_surface_0004.obj", "pool_surface_0004.ply",
                                          "pool_spray_0004.ply", "pool_air_particles_0004.ply",
                                          "pool_particles_0004.vdb"}));

  // The OBJ (read by tinyobjloader) and the PLY hold the same closed mesh.
  tinyobj::ObjReader obj;
  ASSERT_TRUE(obj.ParseFromFile((folder / "pool_surface_0004.obj").string())) << obj.Error();
  std::ifstream in(folder / "pool_surface_0004.ply", std::ios::binary);
  const testing::PlyFile ply = testing::read_ply(in);
  ASSERT_GT(ply.vertex_count, 200u);  // 272 at R = 4Δx
  EXPECT_EQ(obj.GetAttrib().vertices.size(), 3 * ply.vertex_count);
  sdk::Triangles triangles(static_cast<Eigen::Index>(ply.faces.size() / 3), 3);
  for (size_t f = 0; f < ply.faces.size(); ++f) triangles(f / 3, f % 3) = ply.faces[f];
  EXPECT_TRUE(testing::closed_and_consistently_wound(triangles));
  EXPECT_EQ(obj.GetShapes().at(0).mesh.indices.size(), ply.faces.size());
  for (size_t v = 0; v < ply.vertex_count; ++v) {
    // Uniform velocity: each vertex carries it exactly; each vertex lies within a cell of
    // the sphere (it sits in a cell the surface crosses).
    EXPECT_EQ(ply.value(v, "vx"), 1.0f);
    EXPECT_EQ(ply.value(v, "vy"), 2.0f);
    EXPECT_EQ(ply.value(v, "vz"), 3.0f);
    const Eigen::Vector3d x(ply.value(v, "x"), ply.value(v, "y"), ply.value(v, "z"));
    EXPECT_NEAR((x - Eigen::Vector3d::Constant(0.5)).norm(), 0.25, std::sqrt(3.0) / 16);
  }

  std::ifstream spray_in(folder / "pool_spray_0004.ply", std::ios::binary);
  const testing::PlyFile spray = testing::read_ply(spray_in);
  ASSERT_EQ(spray.vertex_count, 3u);
  EXPECT_EQ(spray.value(1, "y"), 0.5f);
  EXPECT_EQ(spray.value(2, "vz"), 0.9f);
  EXPECT_EQ(spray.value(0, "radius"), 0.1f);
  std::ifstream air_in(folder / "pool_air_particles_0004.ply", std::ios::binary);
  EXPECT_EQ(testing::read_ply(air_in).vertex_count, 0u);  // the double has none
}

TEST_F(LiquidWriterTest, MeshesACellCentredLevelSetWithTheNodeVelocity) {
  // The sphere's φ on the 16^3 cell centres, the velocity on the 17^3 nodes: the writer
  // takes φ at the cells and samples the velocity at each vertex's position.
  const WaterDouble fluid(true, true);
  LiquidWriter writer({{"mesh", {"ply"}}, {"particle_formats", nlohmann::json::array()}}, {});
  writer.begin(run_info());
  writer.write_frame({0, 0.0, {}, &fluid});
  std::ifstream in(m_out / "liquid" / "pool_surface_0000.ply", std::ios::binary);
  ASSERT_TRUE(in.good());
  const testing::PlyFile ply = testing::read_ply(in);
  ASSERT_GT(ply.vertex_count, 200u);
  sdk::Triangles triangles(static_cast<Eigen::Index>(ply.faces.size() / 3), 3);
  for (size_t f = 0; f < ply.faces.size(); ++f) triangles(f / 3, f % 3) = ply.faces[f];
  EXPECT_TRUE(testing::closed_and_consistently_wound(triangles));
  for (size_t v = 0; v < ply.vertex_count; ++v) {
    // Uniform velocity: exact at every vertex; each vertex within a cell of the sphere.
    EXPECT_EQ(ply.value(v, "vx"), 1.0f);
    EXPECT_EQ(ply.value(v, "vy"), 2.0f);
    EXPECT_EQ(ply.value(v, "vz"), 3.0f);
    const Eigen::Vector3d x(ply.value(v, "x"), ply.value(v, "y"), ply.value(v, "z"));
    EXPECT_NEAR((x - Eigen::Vector3d::Constant(0.5)).norm(), 0.25, std::sqrt(3.0) / 16);
  }
}

TEST_F(LiquidWriterTest, WritesNothingForAFluidWithoutALevelSet) {
  const WaterDouble smoke(false);
  LiquidWriter writer(nlohmann::json::object(), {});
  writer.begin(run_info());
  writer.write_frame({0, 0.0, {}, &smoke});
  writer.write_frame({1, 0.0, {}, nullptr});
  EXPECT_TRUE(std::filesystem::is_empty(m_out / "liquid"));
}

TEST_F(LiquidWriterTest, RefusesBadParametersNamingThem) {
  const auto path_of = [](const nlohmann::json& params) {
    try {
      LiquidWriter writer(params, {});
    } catch (const ConfigError& e) {
      return e.json_path();
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(path_of({{"adaptivity", 1.5}}), "/adaptivity");
  EXPECT_EQ(path_of({{"smoothing", -1}}), "/smoothing");
  EXPECT_EQ(path_of({{"mesh", {"obj", "stl"}}}), "/mesh/1");
  EXPECT_EQ(path_of({{"particles", {"foam"}}}), "/particles/0");
  EXPECT_EQ(path_of({{"folder", "../elsewhere"}}), "/folder");
  EXPECT_EQ(path_of({{"every", 0}}), "/every");
}

}  // namespace
}  // namespace shellflow::liquid_writer
