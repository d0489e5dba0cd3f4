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

#include "shellflow/runtime/plugin_instance.hpp"
#include "shellflow/runtime/progress.hpp"
#include "shellflow/runtime/scene.hpp"

namespace shellflow::runtime {

struct RunOptions {
  std::optional<int> frames;                 ///< overrides the scene's /time/frames
  std::optional<std::filesystem::path> out;  ///< default: out/<scene name>
  bool overwrite = false;
  std::function<void(const Progress&)> on_progress;   ///< after each frame
  const std::atomic<bool>* stop_requested = nullptr;  ///< checked after every step
  /// A checkpoint every this many frames (0: none) and on a stop request, in
  /// <out>/checkpoints/, the last two kept (see checkpoint.hpp).
  int checkpoint_every = 10;
  /// Continue the run in `out` from its newest readable checkpoint. Refused when the scene
  /// (run.json's "config"), the plugins or their versions, or the build changed since.
  bool resume = false;
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
  std::optional<long long> resumed_from_step;  ///< set when the run was resumed
  std::string message;  ///< for Interrupted / NumericalFailure: what, where, what to try
};

/// Every plugin of a scene, constructed.
struct ScenePlugins {
  std::optional<PluginInstance<sdk::FluidSolver>> fluid;
  std::vector<PluginInstance<sdk::SolidSolver>> solids;
  std::vector<PluginInstance<sdk::Writer>> writers;
};

/// Constructs every plugin of `scene` as `run` does before its first step (meshes read and
/// checked, keyframes checked, pins resolved, domains checked) and checks that the shells'
/// names are unique; writes nothing. Every plugin is tried even when an earlier one fails,
/// so that one call reports every refusal. This is the whole of `shellflow validate` after
/// load_scene(), and the first thing run_scene() does: both refuse with the same messages.
/// @throw SceneValidationError listing each refusal (file, JSON path, message).
ScenePlugins construct_plugins(const Scene& scene);

/// @throw SceneError, PluginError, IoError before anything is written; IoError later.
/// With options.resume: Error (what changed) when the scene or the plugins differ from the
/// run's run.json, IoError when no checkpoint can be read; nothing is written then.
RunSummary run_scene(const Scene& scene, const RunOptions& options);

}  // namespace shellflow::runtime
