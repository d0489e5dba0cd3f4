// preview.mp4: the end of a run that wrote previews, and `shellflow movie RUN_DIR`.
// Encoding needs ffmpeg: those checks skip, with the reason, where it is not installed; a
// missing ffmpeg must stay a one-line note that never fails the run.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "scratch_folder.hpp"
#include "shell_command.hpp"
#include "test_paths.hpp"

namespace shellflow {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

// 4 frames at 12 fps with every-frame previews of an odd size (the movie pads to even).
constexpr const char* kScene = R"({"name": "drop", "time": {"fps": 12, "frames": 4},
  "solids": [{"plugin": "template_solid", "name": "plate", "nodes": 3}],
  "outputs": [{"plugin": "preview_writer", "camera": {"width": 33, "height": 25}}]})";

using Result = shellflow::testing::ShellResult;
using shellflow::testing::run_shell;

Result sh(const std::string& cmd) { return run_shell(cmd); }

bool have(const std::string& tool) {
  return sh("command -v " + tool).exit_code == 0;
}

class Movie : public testing::ScratchFolder {
 protected:
  /// Runs the scene in m_dir; `env` prefixes the command (as PATH=...).
  Result run(const std::string& env = "") {
    write("scene.json", kScene);
    return sh("cd '" + m_dir.string() + "' && " + env + " " + shellflow::test_paths::cli() +
              " run scene.json");
  }
  fs::path out() const { return m_dir / "out" / "drop"; }
};

TEST_F(Movie, WithoutFfmpegTheRunEndsWithANoteAndSucceeds) {
  // PATH without ffmpeg: only the harness (called by its full path) runs.
  const auto r = run("PATH=/nonexistent");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out() / "previews" / "drop_0004.png")) << r.output;
  EXPECT_FALSE(fs::exists(out() / "preview.mp4"));
  EXPECT_THAT(r.output, HasSubstr("note: ffmpeg is not on PATH, so no preview.mp4"));
  const auto m =
      sh("PATH=/nonexistent " + shellflow::test_paths::cli() + " movie '" + out().string() + "'");
  EXPECT_EQ(m.exit_code, 1) << m.output;
  EXPECT_THAT(m.output, HasSubstr("ffmpeg is not on PATH"));
}

TEST_F(Movie, MovieOfAFolderThatIsNoRunNamesTheProblem) {
  auto r = sh(shellflow::test_paths::cli() + " movie '" + (m_dir / "nope").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("run folder not found"));
  r = sh(shellflow::test_paths::cli() + " movie '" + m_dir.string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.output, HasSubstr("has no run.json"));
}

TEST_F(Movie, RunEndsWithAnH264MovieOfEveryPreviewAtTheRunsFps) {
  if (!have("ffmpeg") || !have("ffprobe"))
    GTEST_SKIP() << "ffmpeg/ffprobe not on PATH (scripts/setup.sh installs the ffmpeg package)";
  const auto r = run();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("encoded 5 previews into"));
  EXPECT_THAT(r.output, Not(HasSubstr("note:")));
  ASSERT_TRUE(fs::exists(out() / "preview.mp4")) << r.output;

  const auto probe = [&] {
    return sh(
        "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
        "stream=codec_name,pix_fmt,width,height,r_frame_rate,nb_read_frames -of "
        "default=noprint_wrappers=1 '" +
        (out() / "preview.mp4").string() + "'");
  };
  auto p = probe();
  ASSERT_EQ(p.exit_code, 0) << p.output;
  EXPECT_THAT(p.output, HasSubstr("codec_name=h264"));
  EXPECT_THAT(p.output, HasSubstr("pix_fmt=yuv420p"));
  EXPECT_THAT(p.output, HasSubstr("width=34"));   // 33 padded to even
  EXPECT_THAT(p.output, HasSubstr("height=26"));  // 25 padded to even
  EXPECT_THAT(p.output, HasSubstr("r_frame_rate=12/1"));
  EXPECT_THAT(p.output, HasSubstr("nb_read_frames=5"));  // frames 0..4

  // `shellflow movie` makes it again afterwards.
  fs::remove(out() / "preview.mp4");
  const auto m = sh(shellflow::test_paths::cli() + " movie '" + out().string() + "'");
  EXPECT_EQ(m.exit_code, 0) << m.output;
  EXPECT_THAT(m.output, HasSubstr("5 previews"));
  p = probe();
  EXPECT_THAT(p.output, HasSubstr("nb_read_frames=5"));
  // Piped (a log), no progress line; at a terminal (util-linux `script` gives it one), a
  // line counting the frames ffmpeg has encoded, up to all of them.
  EXPECT_THAT(m.output, Not(HasSubstr("encoding preview.mp4")));
  if (have("script")) {
    const auto t = sh("script -qec \"" + shellflow::test_paths::cli() + " movie '" +
                      out().string() + "'\" /dev/null");
    EXPECT_EQ(t.exit_code, 0) << t.output;
    EXPECT_THAT(t.output, HasSubstr("encoding preview.mp4: frame 5 of 5"));
  }
}

}  // namespace
}  // namespace shellflow
