// The `shellflow` executable: exit codes, messages, and Ctrl-C during a run.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "scratch_folder.hpp"
#include "shell_command.hpp"
#include "test_paths.hpp"

namespace shellflow {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

using Result = shellflow::testing::ShellResult;

class Cli : public shellflow::testing::ScratchFolder {
 protected:
  Result shellflow(const std::string& args) { return run_in("", args); }
  /// The same, with `dir` as the working folder (where out/<scene name> goes by default).
  Result shellflow_in(const fs::path& dir, const std::string& args) { return run_in(dir, args); }
  Result run_in(const fs::path& dir, const std::string& args) {
    const std::string cd = dir.empty() ? "" : "cd '" + dir.string() + "' && ";
    return shellflow::testing::run_shell(cd + shellflow::test_paths::cli() + " " + args);
  }
  std::string scene(const std::string& body) { return write("scene.json", body).string(); }
};

TEST_F(Cli, ValidateAcceptsAGoodSceneAndNamesTheProblemInABadOne) {
  const auto good = shellflow("validate " + scene(R"({"solids": [{"plugin": "template_solid"}]})"));
  EXPECT_EQ(good.exit_code, 0) << good.output;
  EXPECT_THAT(good.output, HasSubstr("valid scene"));
  const auto bad =
      shellflow("validate " + scene(R"({"solids": [{"plugin": "template_solid", "nodes": 1}]})"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_THAT(bad.output, HasSubstr("scene.json: /solids/0/nodes: expected an integer >= 2"));
}

TEST_F(Cli, MissingSceneFileIsAnInputError) {
  const auto r = shellflow("run " + (m_dir / "nope.json").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("nope.json: no such file"));
}

TEST_F(Cli, PluginsListsTheTemplateWithItsParameters) {
  const auto r = shellflow("plugins");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("template_solid (solid plugin"));
  EXPECT_THAT(r.output, HasSubstr("surface_density: a number > 0 [kg/m^2]"));
}

TEST_F(Cli, NumberBeyondADoubleIsAnInputErrorWithLineAndColumn) {
  // Was "internal error" with exit code 2: nlohmann::json's out_of_range for 1e400.
  const auto file =
      scene("{\"solids\": [{\"plugin\": \"template_solid\"}],\n \"gravity\": [0, 1e400, 0]}");
  for (const char* command : {"validate ", "run "}) {
    const auto r = shellflow(command + file);
    EXPECT_EQ(r.exit_code, 1) << command << r.output;
    EXPECT_THAT(r.output,
                HasSubstr("scene.json: JSON syntax error at line 2, column 17: the number 1e400"));
    EXPECT_THAT(r.output, ::testing::Not(HasSubstr("internal error")));
  }
}

TEST_F(Cli, SceneNameCannotLeadOutOfTheOutputFolder) {
  // Run from m_dir/a/b, where out/../../escaped_<pid> is m_dir/a/escaped_<pid>.
  const std::string name = "escaped_" + std::to_string(::getpid());
  fs::create_directories(m_dir / "a" / "b");
  const auto file = scene(R"({"name": "../../)" + name + R"(", "time": {"frames": 1},
      "solids": [{"plugin": "template_solid"}], "outputs": [{"plugin": "obj_writer"}]})");
  const auto r = shellflow_in(m_dir / "a" / "b", "run " + file);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("scene.json: /name: the scene name '../../" + name + "'"));
  EXPECT_FALSE(fs::exists(m_dir / "a" / name));
  EXPECT_FALSE(fs::exists(m_dir / "a" / "b" / "out"));
}

TEST_F(Cli, ValidateConstructsEveryPluginAsRunDoesAndWritesNothing) {
  // Two problems only construction finds: key times out of order (the schema cannot see
  // it) and a NaN vertex in an OBJ. Before, validate passed this scene and run refused it.
  write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
  const std::string name = "dry_run_" + std::to_string(::getpid());
  const auto file = scene(R"({"name": ")" + name + R"(", "solids": [
      {"plugin": "kinematic_shell", "mesh": {"type": "sphere"},
       "motion": {"type": "keyframes", "keys": [{"time": 1}, {"time": 0.5}]}},
      {"plugin": "mass_spring_cloth", "mesh": {"type": "obj", "file": "nan.obj"}}],
      "outputs": [{"plugin": "obj_writer"}]})");
  const auto validate = shellflow_in(m_dir, "validate " + file);
  EXPECT_EQ(validate.exit_code, 1) << validate.output;
  const std::string keys = "scene.json: /solids/0/motion/keys/1/time: ";
  const std::string nan = "scene.json: /solids/1/mesh/file: " + (m_dir / "nan.obj").string() +
                          ":3: vertex 3 has a non-finite coordinate (y = nan)";
  EXPECT_THAT(validate.output, HasSubstr(keys));  // every problem, not only the first
  EXPECT_THAT(validate.output, HasSubstr(nan));
  const auto run = shellflow_in(m_dir, "run " + file);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_THAT(run.output, HasSubstr(keys));
  EXPECT_THAT(run.output, HasSubstr(nan));
  EXPECT_FALSE(fs::exists(m_dir / "out"));

  // A good scene validates without creating its output folder.
  const auto good = scene(R"({"name": ")" + name + R"(", "solids": [{"plugin": "template_solid"}],
      "outputs": [{"plugin": "obj_writer"}]})");
  const auto ok = shellflow_in(m_dir, "validate " + good);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_FALSE(fs::exists(m_dir / "out"));
}

TEST_F(Cli, CtrlCEndsTheRunWithAReadableLastFrame) {
  // Tiny steps so that the run is still going when the signal arrives.
  const auto file = scene(R"({"time": {"frames": 1000, "max_dt": 1e-5},
      "solids": [{"plugin": "template_solid", "name": "plate"}], "outputs": [{"plugin": "obj_writer"}]})");
  const auto out = m_dir / "out";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    freopen("/dev/null", "w", stderr);
    execl(shellflow::test_paths::cli().c_str(), shellflow::test_paths::cli().c_str(), "run",
          file.c_str(), "--out", out.c_str(), nullptr);
    _exit(127);
  }
  // Wait until frame 1 exists, then interrupt.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / "meshes" / "plate_0001.obj") &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed instead of stopping cleanly";
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const auto run = nlohmann::json::parse(read(out / "run.json"));
  EXPECT_EQ(run["status"], "interrupted");
  const int last = run["last_frame"];
  EXPECT_GE(last, 1);
  EXPECT_LT(last, 1000);
  char name[64];
  std::snprintf(name, sizeof name, "plate_%04d.obj", last);
  const auto last_obj = read(out / "meshes" / name);
  EXPECT_THAT(last_obj, HasSubstr("\nf "));  // a complete mesh, not a torn file

  // Ctrl-C left a checkpoint; --resume continues from it (here to one more frame).
  EXPECT_TRUE(fs::exists(out / "checkpoints")) << "no checkpoint written on Ctrl-C";
  const std::string frames = std::to_string(last + 1);
  const auto both = shellflow("run " + file + " --out " + out.string() +
                              " --resume --overwrite");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_THAT(both.output, HasSubstr("--overwrite"));
  const auto resumed = shellflow("run " + file + " --out " + out.string() +
                                 " --resume --frames " + frames);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_THAT(resumed.output, HasSubstr("resuming"));
  const auto after = nlohmann::json::parse(read(out / "run.json"));
  EXPECT_EQ(after["status"], "completed");
  EXPECT_EQ(after["last_frame"], last + 1);
}

TEST_F(Cli, NewSolidWritesAPluginProjectAndRefusesBadNamesAndNonEmptyFolders) {
  const auto dir = m_dir / "plugin";
  auto r = shellflow("new solid my_plate " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"my_plate.hpp", "my_plate.cpp", "CMakeLists.txt", "my_plate_test.cpp",
                        "scenes/my_plate_drop.json"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const auto source = read(dir / "my_plate.cpp");
  EXPECT_THAT(source,
              HasSubstr(R"(SHELLFLOW_SOLID_PLUGIN(shellflow::my_plate::MyPlate, "my_plate"))"));
  EXPECT_THAT(source, Not(HasSubstr("template_solid")));
  EXPECT_THAT(source, Not(HasSubstr("FallingPlate")));
  EXPECT_THAT(read(dir / "CMakeLists.txt"), HasSubstr("find_package(shellflow 0.1 REQUIRED)"));
  EXPECT_THAT(read(dir / "CMakeLists.txt"),
              HasSubstr("shellflow_add_plugin(my_plate SOURCES my_plate.cpp)"));
  EXPECT_NO_THROW(nlohmann::json::parse(read(dir / "scenes/my_plate_drop.json")));

  r = shellflow("new solid my_plate " + dir.string());  // now non-empty
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("is not empty"));
  for (const char* bad : {"MyPlate", "9lives", "my-plate", "new", "sdk", "a__b"}) {
    r = shellflow(std::string("new solid ") + bad + " " + (m_dir / "other").string());
    EXPECT_EQ(r.exit_code, 1) << bad;
    EXPECT_THAT(r.output, HasSubstr("cannot name a plugin")) << bad;
    EXPECT_FALSE(fs::exists(m_dir / "other")) << bad;
  }
}

}  // namespace
}  // namespace shellflow
