// Bad scenes: each error names the file, the exact JSON path, what was expected and
// what was found. The scenes use the plugins built in this tree.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "shellflow/runtime/plugin_instance.hpp"
#include "shellflow/runtime/scene.hpp"
#include "shellflow/runtime/schema_validator.hpp"
#include "test_paths.hpp"

namespace shellflow::runtime {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kPlugins = shellflow::test_paths::plugin_dir();

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    m_dir = fs::temp_directory_path() /
            ("shellflow_scene_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }

  fs::path write(const std::string& text, const std::string& name = "scene.json") {
    const auto file = m_dir / name;
    std::ofstream(file) << text;
    return file;
  }
  Scene load(const std::string& text) { return load_scene(write(text), {kPlugins}); }

  /// The issues a bad scene produces (fails the test if it loads).
  std::vector<ValidationIssue> issues_of(const std::string& text) {
    try {
      load(text);
    } catch (const SceneValidationError& e) {
      EXPECT_EQ(e.file(), (m_dir / "scene.json").string());
      EXPECT_THAT(e.what(), HasSubstr((m_dir / "scene.json").string()));  // the file is named
      return e.issues();
    }
    ADD_FAILURE() << "scene loaded but should not:\n" << text;
    return {};
  }
  /// Expects exactly one issue, at `path`, whose message contains `needle`.
  void expect_issue(const std::string& text, const std::string& path, const std::string& needle) {
    const auto issues = issues_of(text);
    ASSERT_EQ(issues.size(), 1u) << text;
    EXPECT_EQ(issues[0].json_path, path);
    EXPECT_THAT(issues[0].message, HasSubstr(needle));
  }

  fs::path m_dir;
};

constexpr const char* kPlate = R"({"plugin": "template_solid"})";

std::string with_solid(const std::string& solid, const std::string& extra = "") {
  return R"({"solids": [)" + solid + "]" + extra + "}";
}

TEST_F(SceneFiles, AValidSceneLoadsWithDefaultsFilled) {
  const auto scene = load(with_solid(kPlate));
  ASSERT_EQ(scene.solids.size(), 1u);
  EXPECT_EQ(scene.solids[0].instance_name, "template_solid");
  EXPECT_EQ(scene.solids[0].params["surface_density"], 1.0);
  EXPECT_EQ(scene.time.fps, 24.0);
  EXPECT_EQ(scene.name, "scene");  // the file's stem
}

TEST_F(SceneFiles, JsonSyntaxErrorGivesLineAndColumn) {
  try {
    load("{\n  \"solids\": [\n    {\"plugin\": \"template_solid\",}\n  ]\n}");
    FAIL() << "loaded";
  } catch (const SceneError& e) {
    EXPECT_THAT(e.what(), HasSubstr("line 3, column"));
    EXPECT_THAT(e.what(), HasSubstr("scene.json"));
  }
}

TEST_F(SceneFiles, NumberBeyondADoubleIsASyntaxErrorWithLineAndColumn) {
  // nlohmann::json reports 1e400 as out_of_range without a position; it was an internal
  // error (exit code 2) before.
  for (const char* number : {"1e400", "-1e400"}) {
    try {
      load("{\n  \"solids\": [{\"plugin\": \"template_solid\"}],\n  \"time\": {\"fps\": " +
           std::string(number) + "}\n}");
      FAIL() << "loaded " << number;
    } catch (const SceneValidationError& e) {
      FAIL() << "a validation error, not a syntax error: " << e.what();
    } catch (const SceneError& e) {
      EXPECT_EQ(e.file(), (m_dir / "scene.json").string());
      EXPECT_THAT(e.what(), HasSubstr("scene.json: JSON syntax error at line 3, column 19"));
      EXPECT_THAT(e.what(), HasSubstr("the number " + std::string(number) + " is beyond"));
    }
  }
}

TEST_F(SceneFiles, SceneNameThatLeavesOutIsRefusedAtName) {
  for (const char* name : {"../../x", "a/b", "..", ".hidden", "/abs/x", "with space", ""})
    expect_issue(with_solid(kPlate, R"(, "name": ")" + std::string(name) + "\""), "/name",
                 "must be a plain file name: letters, digits, '_', '-' and '.', not starting "
                 "with '.'");
}

TEST_F(SceneFiles, PlainSceneNamesAreKept) {
  EXPECT_EQ(load(with_solid(kPlate, R"(, "name": "Cup_2-b.v3")")).name, "Cup_2-b.v3");
}

TEST_F(SceneFiles, FileStemStartingWithADotNeedsAName) {
  const auto file = write(with_solid(kPlate), "..json");  // stem "."
  try {
    load_scene(file, {kPlugins});
    FAIL() << "loaded";
  } catch (const SceneValidationError& e) {
    ASSERT_EQ(e.issues().size(), 1u);
    EXPECT_EQ(e.issues()[0].json_path, "/name");
    EXPECT_THAT(e.what(), HasSubstr("..json: /name: the file name '..json' starts with '.'"));
  }
  EXPECT_EQ(load_scene(write(with_solid(kPlate, R"(, "name": "ok")"), "..json"), {kPlugins}).name,
            "ok");
}

TEST_F(SceneFiles, WriterFolderMustStayInsideTheRunFolder) {
  const auto issues = issues_of(
      with_solid(kPlate, R"(, "outputs": [{"plugin": "obj_writer", "folder": "../elsewhere"},
                              {"plugin": "ply_writer", "folder": "/abs/out"},
                              {"plugin": "ply_writer", "folder": "a/../../b"},
                              {"plugin": "obj_writer", "folder": "meshes/cloth", "name": "ok"}])"));
  ASSERT_EQ(issues.size(), 3u);
  EXPECT_EQ(issues[0].json_path, "/outputs/0/folder");
  EXPECT_THAT(issues[0].message, HasSubstr("'../elsewhere' holds a '..' component"));
  EXPECT_EQ(issues[1].json_path, "/outputs/1/folder");
  EXPECT_THAT(issues[1].message, HasSubstr("'/abs/out' is an absolute path"));
  EXPECT_EQ(issues[2].json_path, "/outputs/2/folder");
  EXPECT_THAT(issues[2].message, HasSubstr("a relative path without '..'"));
}

TEST_F(SceneFiles, TopLevelMustBeAnObject) { expect_issue("[1, 2]", "", "found an array of 2"); }

TEST_F(SceneFiles, UnknownTopLevelKeySuggestsTheRightOne) {
  expect_issue(R"({"solids": [{"plugin": "template_solid"}], "solid": []})", "/solid",
               "unknown key 'solid' (did you mean 'solids'?)");
}

TEST_F(SceneFiles, FpsMustBePositive) {
  expect_issue(with_solid(kPlate, R"(, "time": {"fps": 0})"), "/time/fps",
               "expected a number > 0 [1/s], found the number 0");
}

TEST_F(SceneFiles, FramesMustBeAnInteger) {
  expect_issue(with_solid(kPlate, R"(, "time": {"frames": 2.5})"), "/time/frames",
               "expected an integer >= 1, found the number 2.5");
}

TEST_F(SceneFiles, GravityNeedsThreeNumbers) {
  expect_issue(with_solid(kPlate, R"(, "gravity": [0, -9.81])"), "/gravity",
               "expected three numbers [x, y, z] [m/s^2], found an array of 2");
}

TEST_F(SceneFiles, SolidsMustBeAnArray) {
  expect_issue(R"({"solids": {"plugin": "template_solid"}})", "/solids", "expected an array, found an object");
}

TEST_F(SceneFiles, SolidWithoutPluginKey) {
  expect_issue(with_solid(R"({"width": 1})"), "/solids/0", "expected \"plugin\": the name of a solid plugin");
}

TEST_F(SceneFiles, UnknownPluginSuggestsTheClosest) {
  expect_issue(with_solid(R"({"plugin": "template_sold"})"), "/solids/0/plugin",
               "did you mean 'template_solid'");
}

TEST_F(SceneFiles, WriterUsedAsSolid) {
  expect_issue(with_solid(R"({"plugin": "obj_writer"})"), "/solids/0/plugin",
               "is a writer plugin, but a solid plugin is needed here");
}

TEST_F(SceneFiles, OutOfRangePluginParameter) {
  expect_issue(with_solid(R"({"plugin": "template_solid", "surface_density": -1})"),
               "/solids/0/surface_density", "expected a number > 0 [kg/m^2], found the number -1");
}

TEST_F(SceneFiles, MisspeltPluginParameter) {
  expect_issue(with_solid(R"({"plugin": "template_solid", "widht": 2})"), "/solids/0/widht",
               "unknown key 'widht' (did you mean 'width'?)");
}

TEST_F(SceneFiles, WrongTypeDeepInsideAPlugin) {
  expect_issue(with_solid(R"({"plugin": "template_solid", "transform": {"translate": "up"}})"),
               "/solids/0/transform/translate", "found the string \"up\"");
}

TEST_F(SceneFiles, UnknownVariantOption) {
  expect_issue(with_solid(R"({"plugin": "kinematic_shell", "mesh": {"type": "sphre"}})"),
               "/solids/0/mesh/type", "did you mean 'sphere'");
}

TEST_F(SceneFiles, VariantWithoutItsKey) {
  expect_issue(with_solid(R"({"plugin": "kinematic_shell", "mesh": {"radius": 1}})"), "/solids/0/mesh",
               "missing required key 'type'");
}

TEST_F(SceneFiles, MissingMeshFileIsResolvedFromTheSceneFolder) {
  expect_issue(with_solid(R"({"plugin": "kinematic_shell", "mesh": {"type": "obj", "file": "cup.obj"}})"),
               "/solids/0/mesh/file", "file not found: " + (m_dir / "cup.obj").string());
}

TEST_F(SceneFiles, TooFewKeyframes) {
  expect_issue(with_solid(R"({"plugin": "kinematic_shell", "mesh": {"type": "sphere"},
                              "motion": {"type": "keyframes", "keys": [{"time": 0}]}})"),
               "/solids/0/motion/keys", "expected at least 2 entries, found 1");
}

TEST_F(SceneFiles, DuplicateInstanceNames) {
  expect_issue(R"({"solids": [{"plugin": "template_solid", "name": "a"}, {"plugin": "template_solid", "name": "a"}]})",
               "/solids/1/name", "the name 'a' is already used");
}

TEST_F(SceneFiles, UnknownCouplingScheme) {
  expect_issue(with_solid(kPlate, R"(, "coupling": {"scheme": "staggerd"})"), "/coupling/scheme",
               "expected one of 'staggered', found the string \"staggerd\" (did you mean 'staggered'?)");
}

TEST_F(SceneFiles, NothingToSimulate) { expect_issue("{}", "", "nothing to simulate"); }

TEST_F(SceneFiles, MissingPluginPathFolder) {
  expect_issue(with_solid(kPlate, R"(, "plugin_path": ["no_such_folder"])"), "/plugin_path/0",
               "folder not found: " + (m_dir / "no_such_folder").string());
}

TEST_F(SceneFiles, WriterParameterOutOfRange) {
  expect_issue(with_solid(kPlate, R"(, "outputs": [{"plugin": "obj_writer", "every": 0}])"),
               "/outputs/0/every", "expected an integer >= 1, found the number 0");
}

TEST_F(SceneFiles, NameWithSlash) {
  expect_issue(with_solid(R"({"plugin": "template_solid", "name": "a/b"})"), "/solids/0/name",
               "may not contain '/'");
}

TEST_F(SceneFiles, EveryProblemIsReportedAtOnce) {
  const auto issues = issues_of(
      R"({"solids": [{"plugin": "template_solid", "width": -2, "nodes": "many"}], "time": {"fps": -1}})");
  ASSERT_EQ(issues.size(), 3u);
  std::vector<std::string> paths;
  for (const auto& i : issues) paths.push_back(i.json_path);
  EXPECT_THAT(paths, ::testing::UnorderedElementsAre("/solids/0/width", "/solids/0/nodes", "/time/fps"));
}

TEST_F(SceneFiles, PluginRejectionKeepsItsPath) {
  // Key times the schema cannot check: the plugin throws ConfigError("/motion/keys/1/time").
  const auto scene = load(with_solid(R"({"plugin": "kinematic_shell", "mesh": {"type": "sphere"},
      "motion": {"type": "keyframes", "keys": [{"time": 1}, {"time": 0.5}]}})"));
  try {
    create_solid(scene, scene.solids[0]);
    FAIL() << "created";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/motion/keys/1/time");
    EXPECT_THAT(e.what(), HasSubstr("kinematic_shell"));
  }
}

}  // namespace
}  // namespace shellflow::runtime
