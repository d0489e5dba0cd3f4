#pragma once
// Writer: observes the run frame by frame and writes files under the run's folder.

#include <filesystem>
#include <string>

#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::sdk {

class FluidSolver;

/// Where and what a run writes; given to each writer before the first frame.
struct RunInfo {
  std::filesystem::path out_dir;  ///< out/<scene>/, exists and is empty of frames
  std::string scene_name;
  double fps = 24.0;
};

/// One frame as writers see it. `fluid` is null in a solids-only scene.
struct FrameView {
  int frame = 0;      ///< 0 is the initial state
  double time = 0.0;  ///< [s]
  ShellSet shells;
  const FluidSolver* fluid = nullptr;
};

/// Why `folder` cannot be a sub-folder of the run's output folder, or "" when it can: it
/// must be a non-empty relative path without ".." components, so that a writer's files stay
/// inside out/<scene>/ (an absolute path would replace the run folder, ".." leave it).
std::string subfolder_problem(const std::string& folder);

/// subfolder_problem() as a ConfigError at `json_path` (a writer's "folder" parameter).
void check_subfolder(const std::string& folder, const std::string& json_path);

/// Creates (if needed) the sub-folder `name` of the run's output folder, where a writer
/// puts its files, and returns it. @throw IoError naming the folder, also when `name`
/// would leave the run folder (see subfolder_problem).
std::filesystem::path make_output_subfolder(const RunInfo& info, const std::string& name);

class Writer {
 public:
  virtual ~Writer() = default;
  virtual void begin(const RunInfo& /*info*/) {}
  /// Must leave complete files (write to a temporary name, then rename) so that a run
  /// stopped at any moment keeps readable frames.
  virtual void write_frame(const FrameView& frame) = 0;
  virtual void end() {}
};

}  // namespace shellflow::sdk
