// `shellflow run` end to end through the library: what a run writes, how it refuses to
// overwrite, and how a non-finite value or a stop request ends it.

#include "shellflow/runtime/run_driver.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "scratch_folder.hpp"
#include "shellflow/runtime/schema_validator.hpp"
#include "shellflow/sdk/error.hpp"
#include "test_paths.hpp"

namespace shellflow::runtime {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Json = nlohmann::json;

const fs::path kPlugins = shellflow::test_paths::plugin_dir();
const fs::path kDoubles = fs::path(shellflow::test_paths::bad_plugin_dir()) / "run_doubles";

class RunDriver : public shellflow::testing::ScratchFolder {
 protected:
  Scene scene(const std::string& solids, int frames = 3) {
    const auto file = write("scene.json", R"({"name": "t", "time": {"fps": 24, "frames": )" +
                                              std::to_string(frames) + R"(}, "solids": [)" + solids +
                                              R"(], "outputs": [{"plugin": "obj_writer"}]})");
    return load_scene(file, {kDoubles, kPlugins});
  }
  RunOptions options() {
    RunOptions o;
    o.out = m_dir / "out";
    return o;
  }
  Json run_json() { return Json::parse(read(m_dir / "out" / "run.json")); }
  size_t metrics_lines() {
    const auto text = read(m_dir / "out" / "metrics.csv");
    return static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  }
};

constexpr const char* kPlate = R"({"plugin": "template_solid", "name": "plate"})";

TEST_F(RunDriver, WritesEveryFrameMetricsAndRunJson) {
  const auto summary = run_scene(scene(kPlate, 3), options());
  EXPECT_EQ(summary.status, RunStatus::Completed);
  EXPECT_EQ(summary.frames_written, 4);  // frames 0..3
  EXPECT_NEAR(summary.sim_time, 3.0 / 24.0, 1e-15);  // steps land on frame times
  for (int f = 0; f <= 3; ++f)
    EXPECT_TRUE(fs::exists(m_dir / "out" / "meshes" / ("plate_000" + std::to_string(f) + ".obj")));
  EXPECT_EQ(metrics_lines(), size_t(summary.steps) + 1);  // header + one row per step
  const auto run = run_json();
  EXPECT_EQ(run["status"], "completed");
  EXPECT_EQ(run["frames_written"], 4);
  EXPECT_EQ(run["config"]["solids"][0]["surface_density"], 1.0);  // defaults echoed
  EXPECT_EQ(run["plan"][0]["module"], "fluid");
  EXPECT_EQ(run["plan"][0]["enabled"], false);
  EXPECT_THAT(run["metrics_columns"].dump(), HasSubstr("plate.kinetic_energy"));
}

TEST_F(RunDriver, RefusesToOverwriteAFinishedRunUnlessAsked) {
  const auto s = scene(kPlate, 1);
  run_scene(s, options());
  const auto before = read(m_dir / "out" / "run.json");
  try {
    run_scene(s, options());
    FAIL() << "overwrote a finished run";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("already holds a run"));
    EXPECT_THAT(e.what(), HasSubstr("--overwrite"));
  }
  EXPECT_EQ(read(m_dir / "out" / "run.json"), before);  // nothing touched
  auto o = options();
  o.overwrite = true;
  EXPECT_EQ(run_scene(s, o).status, RunStatus::Completed);
}

TEST_F(RunDriver, NeverWritesIntoAFolderThatIsNotARun) {
  fs::create_directories(m_dir / "out");
  write("out/notes.txt", "mine");
  auto o = options();
  o.overwrite = true;  // even when asked
  EXPECT_THROW(run_scene(scene(kPlate, 1), o), IoError);
  EXPECT_EQ(read(m_dir / "out" / "notes.txt"), "mine");
}

TEST_F(RunDriver, NonFiniteValueStopsWithTheLastGoodFrameAndSaysWhere) {
  // 1/96 s steps: 4 per frame; the solid turns NaN at its 6th step (start of frame 2).
  const auto summary =
      run_scene(scene(R"({"plugin": "nan_solid", "nan_after_steps": 6, "stable_dt": 0.010416666666666666})", 5),
                options());
  EXPECT_EQ(summary.status, RunStatus::NumericalFailure);
  EXPECT_EQ(summary.last_frame, 1);
  EXPECT_EQ(summary.steps, 6);
  EXPECT_THAT(summary.message, HasSubstr("shell 'nan_solid' node 1 position"));
  EXPECT_THAT(summary.message, HasSubstr("step 6"));
  EXPECT_THAT(summary.message, HasSubstr("last good frame is frame 1"));
  EXPECT_TRUE(fs::exists(m_dir / "out" / "meshes" / "nan_solid_0001.obj"));
  EXPECT_FALSE(fs::exists(m_dir / "out" / "meshes" / "nan_solid_0002.obj"));
  EXPECT_EQ(run_json()["status"], "numerical_failure");
  EXPECT_EQ(run_json()["last_frame"], 1);
}

TEST_F(RunDriver, RunawaySpeedStopsWithTheLastGoodFrameAndTheLikelyCause) {
  // The plate falls freely (g = 9.81 m/s², one step per 1/24 s frame): 0.41 m/s after
  // frame 1, 0.82 m/s after frame 2 — past a guard of 0.5 m/s at step 2.
  const auto file = write("scene.json", R"({"name": "t", "time": {"fps": 24, "frames": 4},
      "coupling": {"max_speed": 0.5}, "solids": [{"plugin": "template_solid", "name": "plate"}],
      "outputs": [{"plugin": "obj_writer"}]})");
  const auto summary = run_scene(load_scene(file, {kDoubles, kPlugins}), options());
  EXPECT_EQ(summary.status, RunStatus::NumericalFailure);
  EXPECT_EQ(summary.steps, 2);
  EXPECT_EQ(summary.last_frame, 1);
  EXPECT_THAT(summary.message, HasSubstr("unstable at step 2"));
  EXPECT_THAT(summary.message, HasSubstr("shell 'plate' node 0 moves at 0.8175"));
  EXPECT_THAT(summary.message, HasSubstr("/coupling/max_speed"));
  EXPECT_THAT(summary.message, HasSubstr("lower /time/max_dt"));
  EXPECT_THAT(summary.message, HasSubstr("last good frame is frame 1"));
  EXPECT_TRUE(fs::exists(m_dir / "out" / "meshes" / "plate_0001.obj"));
  EXPECT_FALSE(fs::exists(m_dir / "out" / "meshes" / "plate_0002.obj"));
  EXPECT_EQ(run_json()["status"], "numerical_failure");
}

TEST_F(RunDriver, StopRequestWritesThePartialFrameAndSaysSo) {
  std::atomic<bool> stop{true};  // as if Ctrl-C came during the first step
  auto o = options();
  o.stop_requested = &stop;
  const auto summary = run_scene(scene(R"({"plugin": "nan_solid", "stable_dt": 0.01})", 5), o);
  EXPECT_EQ(summary.status, RunStatus::Interrupted);
  EXPECT_EQ(summary.steps, 1);
  EXPECT_EQ(summary.last_frame, 1);
  EXPECT_NEAR(summary.sim_time, 0.01, 1e-15);
  EXPECT_TRUE(fs::exists(m_dir / "out" / "meshes" / "nan_solid_0001.obj"));
  EXPECT_THAT(summary.message, HasSubstr("partial frame"));
  EXPECT_EQ(run_json()["status"], "interrupted");
}

TEST_F(RunDriver, PluginRejectionHappensBeforeAnythingIsWritten) {
  try {
    run_scene(scene(R"({"plugin": "nan_solid", "reject": true})"), options());
    FAIL() << "ran";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/reject");
  }
  EXPECT_FALSE(fs::exists(m_dir / "out"));
}

TEST_F(RunDriver, EveryConstructionRefusalIsReportedBeforeAnythingIsWritten) {
  // construct_plugins() is what `shellflow validate` runs: it tries every plugin.
  const auto s = scene(R"({"plugin": "nan_solid", "reject": true},
                          {"plugin": "template_solid", "name": "plate"},
                          {"plugin": "nan_solid", "name": "second", "reject": true})");
  for (int pass = 0; pass < 2; ++pass) {
    try {
      if (pass == 0)
        construct_plugins(s);
      else
        run_scene(s, options());
      FAIL() << "constructed";
    } catch (const SceneValidationError& e) {
      ASSERT_EQ(e.issues().size(), 2u) << e.what();
      EXPECT_EQ(e.issues()[0].json_path, "/solids/0/reject");
      EXPECT_EQ(e.issues()[1].json_path, "/solids/2/reject");
      EXPECT_THAT(e.what(), HasSubstr("scene.json: /solids/2/reject: rejected on purpose"));
    }
  }
  EXPECT_FALSE(fs::exists(m_dir / "out"));
}

}  // namespace
}  // namespace shellflow::runtime
