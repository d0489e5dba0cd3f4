#pragma once
// A bench spec (`shellflow bench SPEC.json`): a base scene, the axes to sweep (JSON
// pointers into the scene with their values) and the error measures to take from each
// run. Validated like a scene: every problem is reported with the spec file and its JSON
// path, all at once (runtime::SceneValidationError).
//
//   {"name": "still_water", "scene": "../verify/water_pool_at_rest.json", "frames": 24,
//    "sweep": [{"pointer": "/fluid/resolution", "values": [8, 16, 32], "small": [8, 12],
//               "spacing": "inverse"}],
//    "measures": [{"measure": "still_fluid_speed"}]}

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "shellflow/runtime/plugin_registry.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::bench {

/// How a swept value relates to the grid spacing or time step h, for the observed order
/// of convergence (error ~ h^p).
enum class Spacing {
  None,     ///< not a refinement axis (a solver setting, a density)
  Value,    ///< the value is h itself (a time step, a tolerance)
  Inverse,  ///< h is proportional to 1 / value (cells along an axis, steps per frame)
};

struct SweepAxis {
  std::string pointer;                 ///< RFC 6901 pointer into the scene, e.g. /fluid/resolution
  std::vector<nlohmann::json> values;  ///< the full sweep, or the small one with --small
  std::string values_path;             ///< where they are in the spec: /sweep/<i>/values
  Spacing spacing = Spacing::None;
  /// A short column name for results.csv: the pointer's last two segments joined by '.'
  std::string label;
};

struct MeasureSpec {
  std::string json_path;  ///< /measures/<i>, for messages
  std::string measure;    ///< the registry name, e.g. still_fluid_speed
  std::string label;      ///< the results.csv column (the "label" key, default: measure)
  nlohmann::json params;  ///< validated, defaults and scene-derived columns filled in
};

struct BenchSpec {
  std::filesystem::path file;  ///< absolute
  std::string name;            ///< "name", or the file's stem
  std::string description;
  std::filesystem::path scene_file;  ///< absolute
  std::optional<int> frames;         ///< overrides the scene's /time/frames
  bool keep_outputs = false;         ///< keep the scene's writers (off: metrics only)
  std::vector<SweepAxis> axes;
  std::vector<MeasureSpec> measures;
  nlohmann::json base_scene;      ///< the scene file as written (sweeps apply to this)
  nlohmann::json resolved_scene;  ///< the base scene validated, defaults filled in
  std::vector<std::filesystem::path> plugin_dirs;  ///< searched after the scene's plugin_path
};

/// The spec file's own schema (measures come from the registry in error_measures.hpp).
sdk::Schema bench_spec_schema();

/// Reads and validates a spec and its base scene. With `small`, each axis takes its
/// "small" values (the test suite's few points) and "small_frames" replaces "frames".
/// Checks: the spec's schema; each pointer addresses a value of the resolved base scene
/// (so a typo is caught before anything runs); each measure is known, its parameters
/// valid, and the columns it reads belong to an instance the scene has.
/// @throw IoError (unreadable file), SceneError (syntax), runtime::SceneValidationError.
BenchSpec load_bench_spec(const std::filesystem::path& file, bool small,
                          const std::vector<std::filesystem::path>& plugin_dirs =
                              runtime::PluginRegistry::default_search_dirs());

std::string to_string(Spacing spacing);

}  // namespace shellflow::bench
