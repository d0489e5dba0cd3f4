#pragma once
// `shellflow run`: creates the scene's plugins, advances the §6 loop frame by frame,
// lets writers observe each frame, and writes out/<scene>/ with metrics.csv and run.json.
// A stop request (Ctrl-C) or a non-finite value ends the run cleanly: every finished frame
// stays readable and run.json says what happened and where.

#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "shellflow/runtime/progress.hpp"
#include "shellflow/runtime/scene.hpp"

namespace shellflow::runtime {

struct RunOptions {
  std::optional<int> frames;                 ///< overrides the scene's /time/frames
  std::optional<std::filesystem::path> out;  ///< default: out/<scene name>
  bool overwrite = false;
  std::function<void(const Progress&)> on_progress;   ///< after each frame
  const std::atomic<bool>* stop_requested = nullptr;  ///< checked after every step
};

enum class RunStatus { Completed, Interrupted, NumericalFailure, Failed };
std::string to_string(RunStatus status);

struct RunSummary {
  RunStatus status = RunStatus::Completed;
  std::filesystem::path out_dir;
  int frames_written = 0;  ///< including frame 0
  int last_frame = 0;
  double sim_time = 0.0;
  long long steps = 0;
  double wall_seconds = 0.0;
  std::string message;  ///< for Interrupted / NumericalFailure: what, where, what to try
};

/// @throw SceneError, PluginError, IoError before anything is written; IoError later.
RunSummary run_scene(const Scene& scene, const RunOptions& options);

}  // namespace shellflow::runtime
