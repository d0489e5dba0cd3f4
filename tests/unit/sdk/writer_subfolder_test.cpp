// A writer's "folder" stays inside the run's output folder: the rule (subfolder_problem),
// its ConfigError form for writers' constructors, and make_output_subfolder's own refusal.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::sdk {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

TEST(WriterSubfolder, RelativePathsWithoutDotDotAreAllowed) {
  for (const char* ok : {"meshes", "previews/front", "a/./b", "v1.2", "..hidden_but_fine"})
    EXPECT_EQ(subfolder_problem(ok), "") << ok;
}

TEST(WriterSubfolder, AbsoluteEmptyAndDotDotAreRefusedSayingWhatIsAllowed) {
  EXPECT_THAT(subfolder_problem("/abs/x"), HasSubstr("'/abs/x' is an absolute path"));
  EXPECT_THAT(subfolder_problem(""), HasSubstr("the folder is empty"));
  for (const char* bad : {"..", "../x", "a/../../b", "a/.."})
    EXPECT_THAT(subfolder_problem(bad), HasSubstr("holds a '..' component")) << bad;
  EXPECT_THAT(subfolder_problem("../x"), HasSubstr("a relative path without '..'"));
}

TEST(WriterSubfolder, CheckThrowsAConfigErrorAtTheParameter) {
  try {
    check_subfolder("../x", "/folder");
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/folder");
  }
  EXPECT_NO_THROW(check_subfolder("meshes", "/folder"));
}

TEST(WriterSubfolder, MakeOutputSubfolderCreatesNothingOutsideTheRun) {
  const fs::path root =
      fs::temp_directory_path() / ("shellflow_subfolder_" + std::to_string(::getpid()));
  fs::create_directories(root / "run");
  const RunInfo info{root / "run", "scene", 24.0};
  EXPECT_THROW(make_output_subfolder(info, "../escaped"), IoError);
  EXPECT_THROW(make_output_subfolder(info, (root / "abs").string()), IoError);
  EXPECT_FALSE(fs::exists(root / "escaped"));
  EXPECT_FALSE(fs::exists(root / "abs"));
  EXPECT_EQ(make_output_subfolder(info, "meshes/a"), root / "run" / "meshes/a");
  EXPECT_TRUE(fs::is_directory(root / "run" / "meshes" / "a"));
  fs::remove_all(root);
}

}  // namespace
}  // namespace shellflow::sdk
