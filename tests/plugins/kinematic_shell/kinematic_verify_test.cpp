// End to end: `shellflow run` on the configs/verify/kinematic_*.json scenes, checking the
// known answers their descriptions state against the files the writers leave.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>
#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;

// The scenes' positions are O(1) m after 48 steps of t += 1/24: round-off ≈ 1e-15.
constexpr double kRoundOff = 1e-12;

class KinematicVerify : public ::testing::Test {
 protected:
  void SetUp() override {
    m_out =
        fs::temp_directory_path() / ("shellflow_kinematic_verify_" + std::to_string(::getpid()));
    fs::remove_all(m_out);
  }
  void TearDown() override { fs::remove_all(m_out); }

  void run(const std::string& scene) {
    const std::string command = shellflow::test_paths::cli() + " run " +
                                shellflow::test_paths::source_dir() + "/configs/verify/" + scene +
                                " --out " + m_out.string() + " > " +
                                (fs::temp_directory_path() / "shellflow_kv.log").string() + " 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }

  fs::path m_out;
};

/// The "v" lines of an OBJ file, parsed with strtod (exact: the writer's decimals round-trip).
std::vector<std::array<double, 3>> obj_nodes(const fs::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in) << file;
  std::vector<std::array<double, 3>> nodes;
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("v ", 0) == 0) {
      std::array<double, 3> p{};
      const char* s = line.c_str() + 2;
      for (double& x : p) {
        char* end = nullptr;
        x = std::strtod(s, &end);
        s = end;
      }
      nodes.push_back(p);
    }
  return nodes;
}

/// Vertex records (x y z vx vy vz as float) of a ply_writer file.
std::vector<std::array<float, 6>> ply_vertices(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  EXPECT_TRUE(in) << file;
  std::string line;
  size_t count = 0;
  while (std::getline(in, line) && line != "end_header")
    if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
  std::vector<std::array<float, 6>> vertices(count);
  in.read(reinterpret_cast<char*>(vertices.data()),
          static_cast<std::streamsize>(count * sizeof(vertices[0])));  // x86: little endian
  EXPECT_TRUE(in) << file;
  return vertices;
}

TEST_F(KinematicVerify, AnalyticCupIsBackAfterOneTurnShiftedByVT) {
  run("kinematic_analytic_cup.json");
  const auto start = obj_nodes(m_out / "meshes" / "cup_0000.obj");
  const auto half = obj_nodes(m_out / "meshes" / "cup_0024.obj");
  const auto turn = obj_nodes(m_out / "meshes" / "cup_0048.obj");
  ASSERT_EQ(start.size(), 24u * 5 + 1);  // 5 rings of 24 + the cap's centre
  ASSERT_EQ(turn.size(), start.size());
  for (size_t i = 0; i < start.size(); ++i) {
    // t = 2 s: one full turn (π rad/s), centre moved by v t = (0.5, 0, 0).
    EXPECT_NEAR(turn[i][0], start[i][0] + 0.5, kRoundOff);
    EXPECT_NEAR(turn[i][1], start[i][1], kRoundOff);
    EXPECT_NEAR(turn[i][2], start[i][2], kRoundOff);
    // t = 1 s: half a turn about the vertical through c + v t = (0.75, ·, 0.5).
    EXPECT_NEAR(half[i][0] - 0.75, -(start[i][0] - 0.5), kRoundOff);
    EXPECT_NEAR(half[i][2] - 0.5, -(start[i][2] - 0.5), kRoundOff);
  }
  // PLY velocities: v + ω × (x − c(t)) at t = 1 s, to float precision (2^-24 relative of
  // |v| ≤ 0.25 + π · 0.2 m/s: below 1e-7).
  const auto vertices = ply_vertices(m_out / "meshes" / "cup_0024.ply");
  ASSERT_EQ(vertices.size(), start.size());
  const double w = std::numbers::pi;
  for (const auto& p : vertices) {
    const double rx = p[0] - 0.75, rz = p[2] - 0.5;
    EXPECT_NEAR(p[3], 0.25 + w * rz, 1e-6);  // (ω × r).x = ω_y r_z
    EXPECT_NEAR(p[4], 0.0, 1e-6);
    EXPECT_NEAR(p[5], -w * rx, 1e-6);  // (ω × r).z = −ω_y r_x
  }
}

TEST_F(KinematicVerify, KeyframedPaddleHoldsItsLastPoseAtRest) {
  run("kinematic_keyframes_paddle.json");
  const auto at_last_key = ply_vertices(m_out / "paddle" / "paddle_0036.ply");
  const auto later = ply_vertices(m_out / "paddle" / "paddle_0048.ply");
  const auto moving = ply_vertices(m_out / "paddle" / "paddle_0024.ply");
  ASSERT_EQ(at_last_key.size(), 81u);
  float moving_speed = 0;
  for (size_t i = 0; i < later.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(later[i][c], at_last_key[i][c]);  // the pose holds exactly
      EXPECT_EQ(later[i][3 + c], 0.0f);
      EXPECT_EQ(at_last_key[i][3 + c], 0.0f);
    }
    moving_speed = std::max(moving_speed, std::abs(moving[i][3]) + std::abs(moving[i][4]));
  }
  EXPECT_GT(moving_speed, 0.1f) << "between keys the paddle moves";
}

}  // namespace
