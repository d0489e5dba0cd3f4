// Bench specs are validated like scenes: every problem names the spec file and its JSON
// path (a pointer the scene lacks, an unknown measure, a swept value the scene's schema
// refuses), and the sweep is the cartesian product of the axes.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "shellflow/bench/bench_spec.hpp"
#include "shellflow/bench/sweep_plan.hpp"
#include "shellflow/runtime/schema_validator.hpp"
#include "test_paths.hpp"

namespace shellflow::bench {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kPlugins = shellflow::test_paths::plugin_dir();

class BenchSpecFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("shellflow_bench_spec_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    fs::create_directories(m_dir);
    write("drop.json", R"({"name": "drop", "time": {"fps": 24, "frames": 6},
      "solids": [{"plugin": "template_solid", "name": "plate", "nodes": 3,
                  "transform": {"translate": [0, 2, 0]}}]})");
  }
  void TearDown() override { fs::remove_all(m_dir); }

  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(m_dir / name) << text;
    return m_dir / name;
  }
  BenchSpec load(const std::string& text, bool small = false) {
    return load_bench_spec(write("spec.json", text), small, {kPlugins});
  }
  /// The issues of a bad spec (fails the test if it loads).
  std::vector<runtime::ValidationIssue> issues_of(const std::string& text) {
    try {
      plan_sweep(load(text));
    } catch (const runtime::SceneValidationError& e) {
      EXPECT_EQ(e.file(), (m_dir / "spec.json").string());
      return e.issues();
    }
    ADD_FAILURE() << "spec loaded but should not:\n" << text;
    return {};
  }
  void expect_issue(const std::string& text, const std::string& path, const std::string& needle) {
    const auto issues = issues_of(text);
    ASSERT_EQ(issues.size(), 1u) << text;
    EXPECT_EQ(issues[0].json_path, path);
    EXPECT_THAT(issues[0].message, HasSubstr(needle));
  }

  fs::path m_dir;
};

TEST_F(BenchSpecFiles, BadPointerIsRejectedAtItsPathWithASuggestion) {
  expect_issue(R"({"scene": "drop.json",
    "sweep": [{"pointer": "/solids/0/surface_densty", "values": [1, 2]}]})",
               "/sweep/0/pointer", "did you mean 'surface_density'");
  // Past the end of an array.
  expect_issue(
      R"({"scene": "drop.json", "sweep": [{"pointer": "/solids/3/nodes", "values": [3]}]})",
      "/sweep/0/pointer", "an array of 1");
  // Not a pointer at all.
  expect_issue(R"({"scene": "drop.json", "sweep": [{"pointer": "time/fps", "values": [3]}]})",
               "/sweep/0/pointer", "not a JSON pointer");
}

TEST_F(BenchSpecFiles, DefaultsOfTheSceneCanBeSwept) {
  // /time/cfl and /coupling/max_speed are not in the file: the resolved scene has them.
  const auto spec = load(R"({"scene": "drop.json",
    "sweep": [{"pointer": "/coupling/max_speed", "values": [1, 2]}]})");
  ASSERT_EQ(spec.axes.size(), 1u);
  EXPECT_EQ(spec.axes[0].label, "coupling.max_speed");
}

TEST_F(BenchSpecFiles, UnknownMeasureIsRejectedAtItsPath) {
  expect_issue(R"({"scene": "drop.json", "measures": [{"measure": "free_fal"}]})",
               "/measures/0/measure", "did you mean 'free_fall'");
}

TEST_F(BenchSpecFiles, MeasureColumnOfAnUnknownInstanceIsRejected) {
  expect_issue(R"({"scene": "drop.json", "measures": [
      {"measure": "free_fall", "column": "plat.height", "initial_height": 2}]})",
               "/measures/0", "instance 'plat'");
  // A measure of the fluid in a scene without one.
  expect_issue(R"({"scene": "drop.json", "measures": [{"measure": "still_fluid_speed"}]})",
               "/measures/0", "no \"fluid\"");
  // A measure's own parameters, checked by its schema: the misspelt key and the missing one.
  const auto issues = issues_of(R"({"scene": "drop.json", "measures": [
      {"measure": "free_fall", "column": "plate.height", "initial_hieght": 2}]})");
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].json_path, "/measures/0/initial_hieght");
  EXPECT_THAT(issues[0].message, HasSubstr("did you mean 'initial_height'"));
  EXPECT_EQ(issues[1].json_path, "/measures/0");
  EXPECT_THAT(issues[1].message, HasSubstr("missing required key 'initial_height'"));
}

TEST_F(BenchSpecFiles, SweptValueTheSceneRefusesNamesTheValueAndTheScenePath) {
  // template_solid takes at least 2 nodes per edge.
  expect_issue(R"({"scene": "drop.json",
    "sweep": [{"pointer": "/solids/0/nodes", "values": [3, 1]}]})",
               "/sweep/0/values/1", "scene /solids/0/nodes");
}

TEST_F(BenchSpecFiles, RefinementAxisTakesPositiveNumbers) {
  expect_issue(R"({"scene": "drop.json", "sweep": [
      {"pointer": "/time/max_dt", "values": [0.01, 0], "spacing": "value"}]})",
               "/sweep/0/values/1", "positive numbers");
}

TEST_F(BenchSpecFiles, SweepIsTheCartesianProductLastAxisFastest) {
  const auto spec = load(R"({"scene": "drop.json", "frames": 4, "sweep": [
      {"pointer": "/solids/0/nodes", "values": [3, 4], "small": [5]},
      {"pointer": "/time/max_dt", "values": [0.01, 0.02, 0.04], "spacing": "value"}]})");
  const auto points = plan_sweep(spec);
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[0].id, "run_001");
  EXPECT_EQ(points[1].scene["solids"][0]["nodes"], 3);
  EXPECT_EQ(points[1].scene["time"]["max_dt"], 0.02);
  EXPECT_EQ(points[5].scene["solids"][0]["nodes"], 4);
  EXPECT_EQ(points[5].scene["time"]["max_dt"], 0.04);
  // Each scene is named after its run and, by default, writes no outputs.
  EXPECT_EQ(points[5].scene["name"], "run_006");
  EXPECT_TRUE(points[5].scene["outputs"].empty());
  EXPECT_EQ(*spec.frames, 4);

  // --small: each axis's "small" values where it has them.
  const auto small = plan_sweep(load(R"({"scene": "drop.json", "sweep": [
      {"pointer": "/solids/0/nodes", "values": [3, 4], "small": [5]},
      {"pointer": "/time/max_dt", "values": [0.01, 0.02]}]})",
                                     true));
  ASSERT_EQ(small.size(), 2u);
  EXPECT_EQ(small[1].scene["solids"][0]["nodes"], 5);
}

TEST_F(BenchSpecFiles, EveryProblemIsReportedAtOnce) {
  const auto issues = issues_of(R"({"scene": "drop.json", "sweeep": [],
    "measures": [{"measure": "nope"}]})");
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].json_path, "/sweeep");
  EXPECT_EQ(issues[1].json_path, "/measures/0/measure");
}

}  // namespace
}  // namespace shellflow::bench
