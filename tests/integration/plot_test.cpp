// `shellflow plot RUN_DIR [COLUMNS...]`: PNGs of metrics.csv columns against time, and the
// errors for a missing run folder and an unknown column (which list the available ones).

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

#include "scratch_folder.hpp"
#include "shell_command.hpp"
#include "test_paths.hpp"

namespace shellflow {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using Result = shellflow::testing::ShellResult;
using shellflow::testing::run_shell;

Result sh(const std::string& cmd) { return run_shell(cmd); }

class Plot : public testing::ScratchFolder {
 protected:
  void SetUp() override {
    ScratchFolder::SetUp();
    write("scene.json", R"({"name": "drop", "time": {"fps": 24, "frames": 6},
      "solids": [{"plugin": "template_solid", "name": "plate", "nodes": 3}]})");
    const auto r =
        sh("cd '" + m_dir.string() + "' && " + shellflow::test_paths::cli() + " run scene.json");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  Result plot(const std::string& args) {
    return sh(shellflow::test_paths::cli() + " plot " + args);
  }
  fs::path out() const { return m_dir / "out" / "drop"; }
};

TEST_F(Plot, DrawsTheChosenColumnsAndTheDefaultOnes) {
  if (sh("/usr/bin/python3 -c 'import matplotlib'").exit_code != 0)
    GTEST_SKIP() << "/usr/bin/python3 cannot import matplotlib (install python3-matplotlib)";
  auto r = plot("'" + out().string() + "' plate.height dt");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* png : {"plate.height.png", "dt.png"}) {
    const auto file = out() / "plots" / png;
    ASSERT_TRUE(fs::exists(file)) << r.output;
    // A PNG signature and more than an empty canvas's few hundred bytes.
    EXPECT_EQ(read(file).substr(1, 3), "PNG");
    EXPECT_GT(fs::file_size(file), 5000u);
  }
  // Without columns: the energies (and volumes, iterations, speeds when present).
  r = plot("'" + out().string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out() / "plots" / "plate.kinetic_energy.png")) << r.output;
}

TEST_F(Plot, UnknownColumnListsTheAvailableOnes) {
  const auto r = plot("'" + out().string() + "' plate.hieght");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("no column 'plate.hieght'"));
  EXPECT_THAT(r.output, HasSubstr("available: "));
  EXPECT_THAT(r.output, HasSubstr("plate.height"));
}

TEST_F(Plot, MissingRunFolderIsAnError) {
  const auto r = plot("'" + (m_dir / "out" / "nope").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("run folder not found"));
}

}  // namespace
}  // namespace shellflow
