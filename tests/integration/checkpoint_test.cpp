// Checkpoint and resume (issue 15, item 5): a run stopped (Ctrl-C) or crashed and then
// resumed writes the same frames and metrics, bit for bit, as a run never stopped; a
// resume refuses a changed scene, naming the change; a damaged newest checkpoint is
// skipped for the older one.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "scratch_folder.hpp"
#include "shellflow/runtime/checkpoint.hpp"
#include "shellflow/runtime/run_driver.hpp"
#include "shellflow/sdk/error.hpp"
#include "test_paths.hpp"

namespace shellflow::runtime {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Json = nlohmann::json;

const fs::path kPlugins = shellflow::test_paths::plugin_dir();

/// Smoke from a source, a cloth and a dynamic Bullet shell, two-way coupled, on a 12^3
/// grid: every kind of state a checkpoint must hold, in about a second per run.
std::string coupled_scene(double cloth_density = 0.2) {
  return R"({"name": "ckpt", "gravity": [0, -9.81, 0],
    "time": {"fps": 24, "frames": 4, "max_dt": 0.01},
    "fluid": {"plugin": "grid_fluid", "name": "air", "resolution": 12,
              "boundary": {"y_max": {"type": "open"}},
              "sources": [{"shape": "sphere", "center": [0.5, 0.2, 0.5], "radius": 0.12,
                           "velocity": [0, 1.5, 0], "density": 1.0}]},
    "solids": [
      {"plugin": "mass_spring_cloth", "name": "cloth",
       "mesh": {"type": "grid", "width": 0.3, "height": 0.3, "nodes_u": 5, "nodes_v": 5},
       "transform": {"rotate_axis": [1, 0, 0], "rotate_deg": 90, "translate": [0.5, 0.6, 0.5]},
       "surface_density": )" +
         std::to_string(cloth_density) + R"(, "pins": {"grid": ["top"]}},
      {"plugin": "bullet_rigid", "name": "rigid", "ground": {"height": 0.0},
       "bodies": [{"name": "box", "mesh": {"type": "box", "size": [0.15, 0.15, 0.15], "divisions": 2},
                   "transform": {"translate": [0.75, 0.4, 0.5]}, "surface_density": 0.5,
                   "velocity": [-0.5, 0.5, 0]}]}],
    "outputs": [{"plugin": "obj_writer"}]})";
}

/// metrics.csv as columns of text (the %.17g text of a double is equal iff the bits are),
/// without the wall-clock columns (phase timings and any "seconds").
std::map<std::string, std::vector<std::string>> numeric_columns(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string c; std::getline(header, c, ',');) names.push_back(c);
  std::map<std::string, std::vector<std::string>> columns;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string value;
    for (const auto& name : names) {
      if (!std::getline(row, value, ',')) value.clear();
      const std::string key =
          name.substr(name.rfind('.') == std::string::npos ? 0 : name.rfind('.') + 1);
      const bool wall_time = key.rfind("t_", 0) == 0 || key.find("seconds") != std::string::npos ||
                             key.find("wall") != std::string::npos;
      if (!wall_time) columns[name].push_back(value);
    }
  }
  return columns;
}

/// Every file under `dir`'s meshes/ folder, by name, with its bytes.
std::map<std::string, std::string> mesh_files(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir / "meshes")) {
    std::ifstream in(e.path(), std::ios::binary);
    files[e.path().filename().string()] = std::string(std::istreambuf_iterator<char>(in), {});
  }
  return files;
}

class Checkpoints : public shellflow::testing::ScratchFolder {
 protected:
  Scene scene(const std::string& json, const std::string& file = "scene.json") {
    return load_scene(write(file, json), {kPlugins});
  }
  RunOptions options(const std::string& out, int every = 2) {
    RunOptions o;
    o.out = m_dir / out;
    o.checkpoint_every = every;
    return o;
  }
  void expect_same_run(const fs::path& a, const fs::path& b) {
    const auto meshes_a = mesh_files(a);
    const auto meshes_b = mesh_files(b);
    ASSERT_EQ(meshes_a.size(), meshes_b.size());
    for (const auto& [name, bytes] : meshes_a) {
      ASSERT_TRUE(meshes_b.count(name)) << name;
      EXPECT_TRUE(meshes_b.at(name) == bytes) << name << " differs between " << a << " and " << b;
    }
    const auto metrics_a = numeric_columns(a / "metrics.csv");
    const auto metrics_b = numeric_columns(b / "metrics.csv");
    ASSERT_EQ(metrics_a.size(), metrics_b.size());
    for (const auto& [name, values] : metrics_a) {
      ASSERT_TRUE(metrics_b.count(name)) << name;
      ASSERT_EQ(values.size(), metrics_b.at(name).size()) << name;
      for (size_t i = 0; i < values.size(); ++i)
        ASSERT_EQ(values[i], metrics_b.at(name)[i]) << name << " row " << i + 1;
    }
  }
};

TEST_F(Checkpoints, StoppedOrCrashedAndResumedRunIsBitIdenticalToAnUninterruptedOne) {
  const auto s = scene(coupled_scene());
  const auto whole = run_scene(s, options("whole"));
  ASSERT_EQ(whole.status, RunStatus::Completed);
  EXPECT_EQ(list_checkpoints(m_dir / "whole").size(), 2u);  // frames 2 and 4 (the last)

  // Ctrl-C after frame 2: the run stops after the first step of frame 3, writes a
  // checkpoint there (within a frame) and the partial frame 3.
  std::atomic<bool> stop{false};
  auto o = options("stopped");
  o.stop_requested = &stop;
  o.on_progress = [&](const Progress& p) {
    if (p.frame == 2) stop = true;
  };
  const auto stopped = run_scene(s, o);
  ASSERT_EQ(stopped.status, RunStatus::Interrupted);
  const auto stopped_checkpoints = list_checkpoints(m_dir / "stopped");
  ASSERT_EQ(stopped_checkpoints.size(), 2u);  // frame 2's and the Ctrl-C one

  // A crash within frame 3 looks like the stopped run without its Ctrl-C checkpoint: the
  // resume goes back to frame 2's and cuts metrics.csv back to it.
  fs::copy(m_dir / "stopped", m_dir / "crashed", fs::copy_options::recursive);
  fs::remove(m_dir / "crashed" / "checkpoints" / stopped_checkpoints[0].filename());
  {
    std::ifstream metrics(m_dir / "crashed" / "metrics.csv");
    const auto rows = std::count(std::istreambuf_iterator<char>(metrics), {}, '\n') - 1;
    EXPECT_GT(rows, read_checkpoint(stopped_checkpoints[1]).meta.step);  // rows to cut
  }

  for (const char* name : {"stopped", "crashed"}) {
    SCOPED_TRACE(name);
    auto r = options(name);
    r.resume = true;
    const auto resumed = run_scene(s, r);
    ASSERT_EQ(resumed.status, RunStatus::Completed);
    ASSERT_TRUE(resumed.resumed_from_step.has_value());
    EXPECT_EQ(resumed.steps, whole.steps);
    EXPECT_EQ(resumed.frames_written, whole.frames_written);
    expect_same_run(m_dir / "whole", m_dir / name);
    std::ifstream in(m_dir / name / "run.json");
    const Json run = Json::parse(in);
    EXPECT_EQ(run["status"], "completed");
    EXPECT_EQ(run["resumed"].size(), 1u);
  }
}

TEST_F(Checkpoints, ResumeRefusesAChangedSceneNamingTheChange) {
  constexpr const char* kPlate =
      R"({"name": "plate", "time": {"fps": 24, "frames": 2},
          "solids": [{"plugin": "template_solid", "name": "plate", "surface_density": 1.0}],
          "outputs": [{"plugin": "obj_writer"}]})";
  ASSERT_EQ(run_scene(scene(kPlate), options("out", 1)).status, RunStatus::Completed);
  const auto run_json_before = read(m_dir / "out" / "run.json");

  std::string changed = kPlate;
  changed.replace(changed.find("1.0"), 3, "2.5");
  auto r = options("out", 1);
  r.resume = true;
  r.frames = 4;
  try {
    run_scene(scene(changed, "changed.json"), r);
    FAIL() << "resumed a run whose scene changed";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot resume"));
    EXPECT_THAT(e.what(), HasSubstr("/solids/0/surface_density was 1.0, now 2.5"));
  }
  EXPECT_EQ(read(m_dir / "out" / "run.json"), run_json_before);  // nothing touched

  // The same scene resumes, and --frames extends the run.
  const auto resumed = run_scene(scene(kPlate), r);
  EXPECT_EQ(resumed.status, RunStatus::Completed);
  EXPECT_EQ(resumed.last_frame, 4);
}

TEST_F(Checkpoints, DamagedNewestCheckpointFallsBackToTheOlderOne) {
  const auto s = scene(coupled_scene());
  auto o = options("whole", 1);
  o.frames = 3;
  const auto whole = run_scene(s, o);
  ASSERT_EQ(whole.status, RunStatus::Completed);

  // The same run stopped after frame 3 whose newest checkpoint (frame 3's) is damaged:
  // one byte flipped in the middle of the state.
  o.out = m_dir / "damaged";
  run_scene(s, o);
  const auto files = list_checkpoints(m_dir / "damaged");
  ASSERT_EQ(files.size(), 2u);
  {
    std::fstream f(files[0], std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(0, std::ios::end);
    const auto middle = f.tellg() / 2;
    f.seekg(middle);
    char c = 0;
    f.read(&c, 1);
    c = static_cast<char>(c ^ 0x5a);
    f.seekp(middle);
    f.write(&c, 1);
  }
  EXPECT_THROW(read_checkpoint(files[0]), IoError);
  const Checkpoint older = read_checkpoint(files[1]);

  auto r = o;
  r.resume = true;
  const auto resumed = run_scene(s, r);
  ASSERT_EQ(resumed.status, RunStatus::Completed);
  EXPECT_EQ(resumed.resumed_from_step, older.meta.step);  // frame 2's, not frame 3's
  expect_same_run(m_dir / "whole", m_dir / "damaged");

  // With every checkpoint unreadable, resume refuses and says so.
  for (const auto& f : list_checkpoints(m_dir / "damaged")) std::ofstream(f) << "junk";
  try {
    run_scene(s, r);
    FAIL() << "resumed without a readable checkpoint";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no readable checkpoint"));
  }
}

}  // namespace
}  // namespace shellflow::runtime
