// Inputs at the edges of what the system and an int can hold, fed to the scene loader as
// text (parse_scene, as tests/fuzz/scene_fuzzer does): each must end in a shellflow error
// at the right JSON path, never in an internal error (a std::exception that is not a
// shellflow::Error: exit code 2) nor in a scene that loads with a wrapped number.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "shellflow/runtime/scene.hpp"
#include "shellflow/runtime/schema_validator.hpp"
#include "shellflow/sdk/error.hpp"
#include "test_paths.hpp"

namespace shellflow::runtime {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kPlugins = shellflow::test_paths::plugin_dir();
// parse_scene never reads it; relative paths resolve next to it, in a folder that exists
// (under a missing folder the system says "no such file" before "name too long").
const fs::path kSceneFile = fs::temp_directory_path() / "shellflow_limits_test.json";
// Longer than any file name component may be (NAME_MAX is 255 on Linux), so the
// system refuses the path with ENAMETOOLONG rather than "no such file".
const std::string kLongName(300, 'a');

/// The issues of a scene that must not load (a std::exception other than a
/// SceneValidationError fails the test, as it would be an internal error in the CLI).
std::vector<ValidationIssue> issues_of(const std::string& text) {
  try {
    parse_scene(text, kSceneFile, {kPlugins});
  } catch (const SceneValidationError& e) {
    return e.issues();
  }
  ADD_FAILURE() << "scene loaded but should not:\n" << text;
  return {};
}

void expect_one_issue(const std::string& text, const std::string& path,
                      const std::vector<std::string>& needles) {
  const auto issues = issues_of(text);
  ASSERT_EQ(issues.size(), 1u) << text;
  EXPECT_EQ(issues[0].json_path, path);
  for (const auto& needle : needles) EXPECT_THAT(issues[0].message, HasSubstr(needle));
}

// Found by review while writing the fuzz target: fs::is_directory without an error_code
// threw filesystem_error ("File name too long"), so `shellflow validate` said "internal
// error" and exited 2.
TEST(SceneInputLimits, PluginPathWithANameTooLongIsAnIssueAtItsPath) {
  expect_one_issue(R"({"plugin_path": [")" + kLongName + R"("], "solids": [{"plugin": "template_solid"}]})",
                   "/plugin_path/0", {"folder not found", "File name too long"});
}

TEST(SceneInputLimits, PluginFileWithANameTooLongIsAPluginErrorAtPlugin) {
  expect_one_issue(R"({"solids": [{"plugin": ")" + kLongName + R"(.so"}]})", "/solids/0/plugin",
                   {"plugin file not found", "File name too long"});
}

TEST(SceneInputLimits, MeshFileWithANameTooLongIsAnIssueAtFile) {
  expect_one_issue(R"({"solids": [{"plugin": "kinematic_shell",
                       "mesh": {"type": "obj", "file": ")" +
                       kLongName + R"("}}]})",
                   "/solids/0/mesh/file", {"file not found", "File name too long"});
}

TEST(SceneInputLimits, SceneFileWithANameTooLongIsAnIoError) {
  try {
    load_scene(kSceneFile.parent_path() / (kLongName + ".json"), {kPlugins});
    FAIL() << "loaded";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot read scene file"));
    EXPECT_THAT(e.what(), HasSubstr("File name too long"));
  }
}

// Found by review: integers are read as int, so 4294967297 frames wrapped to 1 and the
// scene validated and ran one frame without a word.
TEST(SceneInputLimits, FramesBeyondAnIntAreRefusedAtTheirPath) {
  for (const char* frames : {"4294967297", "2147483648", "18446744073709551615"})
    expect_one_issue(std::string(R"({"solids": [{"plugin": "template_solid"}], "time": {"frames": )") +
                         frames + "}}",
                     "/time/frames", {frames, "at most 2147483647"});
}

TEST(SceneInputLimits, LargestIntIsStillAccepted) {
  const auto scene = parse_scene(
      R"({"solids": [{"plugin": "template_solid"}], "time": {"frames": 2147483647}})", kSceneFile,
      {kPlugins});
  EXPECT_EQ(scene.time.frames, 2147483647);
}

TEST(SceneInputLimits, IntegerListEntryBeyondAnIntIsRefusedAtItsIndex) {
  SchemaValidator validator(kSceneFile.parent_path());
  nlohmann::json value = nlohmann::json::parse("[0, -2147483648, -2147483649, 3]");
  validator.validate(value, sdk::Schema::integer_list().json(), "/pins/indices");
  ASSERT_EQ(validator.issues().size(), 1u);
  EXPECT_EQ(validator.issues()[0].json_path, "/pins/indices/2");
  EXPECT_THAT(validator.issues()[0].message, HasSubstr("at most 2147483647"));
}

}  // namespace
}  // namespace shellflow::runtime
