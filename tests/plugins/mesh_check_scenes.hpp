#pragma once
// Broken OBJ meshes and a fixture that puts one into a scene and constructs its plugins as
// `shellflow run` and `validate` do (load_scene + construct_plugins), for the solids' tests
// of their mesh-check policy (geometry::check_mesh). Each mesh has exactly one defect.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "logged_messages.hpp"
#include "shellflow/runtime/run_driver.hpp"
#include "shellflow/runtime/scene.hpp"
#include "test_paths.hpp"

namespace shellflow::testing {

/// A tetrahedron's four faces (lines 1-4 vertices, 5-8 faces): a clean closed mesh.
inline constexpr const char* kCleanObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
/// Three triangles on the edge between vertices 1 and 2 (a fin).
inline constexpr const char* kNonManifoldObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
/// A tetrahedron plus a triangle whose corners 2, 5, 6 (lines 2, 9, 10) are collinear.
inline constexpr const char* kZeroAreaObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"
    "v 2 0 0\nv 3 0 0\nf 2 5 6\n";
/// A tetrahedron plus vertex 5 (line 9), which no face uses.
inline constexpr const char* kLooseVertexObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\nv 5 5 5\n";

class MeshCheckScene : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = std::filesystem::temp_directory_path() /
            (std::string("shellflow_mesh_scene_") + info->test_suite_name() + "_" + info->name() +
             "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(m_dir);
    // Warnings go through spdlog's default logger, which plugins share with the runtime.
    m_log.emplace();
  }
  void TearDown() override {
    m_log.reset();
    std::filesystem::remove_all(m_dir);
  }

  /// Writes `obj` as mesh.obj and a scene with the one solid `solid_json`, whose mesh
  /// refers to "mesh.obj", then constructs its plugins.
  runtime::ScenePlugins construct(const std::string& obj, const std::string& solid_json) {
    std::ofstream(m_dir / "mesh.obj") << obj;
    std::ofstream(scene_file()) << R"({"solids": [)" << solid_json << "]}";
    const auto scene = runtime::load_scene(scene_file(), {shellflow::test_paths::plugin_dir()});
    return runtime::construct_plugins(scene);
  }
  /// The refusal construct() ends with (fails the test if it constructs).
  SceneError refusal(const std::string& obj, const std::string& solid_json) {
    try {
      construct(obj, solid_json);
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), scene_file().string());
      EXPECT_THAT(e.what(), ::testing::HasSubstr(scene_file().string()));
      EXPECT_THAT(e.what(), ::testing::HasSubstr(obj_file().string()));
      return e;
    }
    ADD_FAILURE() << "constructed:\n" << obj;
    return SceneError("", "", "");
  }
  /// Every message logged since SetUp, one per line.
  std::string log() const {
    std::string out;
    for (const auto& line : m_log->lines()) out += line;
    return out;
  }
  std::filesystem::path scene_file() const { return m_dir / "scene.json"; }
  std::filesystem::path obj_file() const { return m_dir / "mesh.obj"; }

  std::filesystem::path m_dir;
  std::optional<LoggedMessages> m_log;
};

}  // namespace shellflow::testing
