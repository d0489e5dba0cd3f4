#pragma once
// preview.mp4 from a run's PNG previews through ffmpeg: what `shellflow run` does at the end
// of a run that wrote previews, and what `shellflow movie RUN_DIR` does afterwards.

#include <cstdio>
#include <filesystem>
#include <string>

namespace shellflow::app {

struct PreviewMovie {
  enum class Status { Written, NoPreviews, NoFfmpeg, Failed };
  Status status = Status::NoPreviews;
  std::filesystem::path file;      ///< RUN_DIR/preview.mp4
  std::filesystem::path previews;  ///< the preview folder read
  int frames = 0;                  ///< PNG files encoded
  double fps = 0.0;                ///< the run's fps divided by the preview writer's "every"
  std::string message;             ///< what went wrong (NoPreviews, NoFfmpeg, Failed)
};

/// The executable `name` on PATH, or empty.
std::filesystem::path find_on_path(const std::string& name);

/// Encodes RUN_DIR/<preview folder>/*.png into RUN_DIR/preview.mp4 (H.264, yuv420p, odd
/// sizes padded to even, the run's fps), the folder and fps read from RUN_DIR/run.json.
/// `progress`, when given (stderr at a terminal), gets a line "encoding preview.mp4: frame k
/// of n" rewritten as ffmpeg goes.
/// @throw shellflow::IoError when RUN_DIR is not a run folder (no readable run.json).
PreviewMovie encode_preview_movie(const std::filesystem::path& run_dir,
                                  std::FILE* progress = nullptr);

}  // namespace shellflow::app
