#pragma once
// A known shell and a scratch output folder for the mesh writer tests.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <set>
#include <string>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::mesh_output::testing {

/// An icosphere moved off the origin by non-representable decimals, with a rotating
/// velocity field, so every coordinate has all 53 bits in use.
inline sdk::ShellSurface known_shell(const std::string& name) {
  auto mesh = geometry::make_sphere(0.3, 1);
  sdk::ShellSurface s;
  s.name = name;
  s.positions = mesh.positions;
  s.positions.rowwise() += Eigen::RowVector3d(0.1, -1.0 / 3.0, 2.0 / 7.0);
  s.velocities.resize(s.positions.rows(), 3);
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    s.velocities.row(i) = Eigen::RowVector3d(0.7, 0.0, -0.2).cross(s.positions.row(i)) +
                          Eigen::RowVector3d(0.0, -9.81 * 0.1, 0.0);
  s.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  s.surface_density = Eigen::VectorXd::Ones(mesh.triangles.rows());
  return s;
}

class MeshWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    m_out = std::filesystem::temp_directory_path() /
            ("shellflow_mesh_writer_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(m_out);
    std::filesystem::create_directories(m_out);
  }
  void TearDown() override { std::filesystem::remove_all(m_out); }

  std::set<std::string> files_in(const std::filesystem::path& folder) const {
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
      names.insert(entry.path().filename().string());
    return names;
  }

  sdk::RunInfo run_info() const { return {m_out, "test", 24.0}; }

  std::filesystem::path m_out;
};

}  // namespace shellflow::mesh_output::testing
