#pragma once
// A scene file, validated as a whole before anything runs: the runtime's own keys
// against its schema, every plugin entry against that plugin's schema. Errors name the
// file and the JSON path of each problem (SceneValidationError lists them all).

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "shellflow/runtime/plugin_registry.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::runtime {

/// One plugin entry of the scene ("fluid", "solids/i", "outputs/i").
struct PluginSpec {
  std::string json_path;  ///< e.g. "/solids/0"
  std::string instance_name;
  std::shared_ptr<PluginLibrary> library;
  nlohmann::json params;  ///< validated, defaults filled, without "plugin" and "name"
};

struct TimeSettings {
  double fps = 24.0;
  int frames = 48;
  std::optional<double> max_dt;  ///< cap on the step [s]
  double cfl = 0.9;
};

struct Scene {
  std::filesystem::path file;  ///< absolute
  std::string name;            ///< "name", or the file's stem
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};
  TimeSettings time;
  std::string coupling_scheme = "staggered";
  /// Stability guard: a fluid or shell speed above this stops the run [m/s].
  double max_speed = 340.0;
  std::optional<PluginSpec> fluid;
  std::vector<PluginSpec> solids;
  std::vector<PluginSpec> outputs;
  nlohmann::json resolved;  ///< the whole scene with defaults filled in (for run.json)
};

/// The runtime's own part of the scene schema (plugin entries are "plugin" nodes).
sdk::Schema scene_schema();

/// True when `name` can be a folder name of its own: letters, digits, '_', '-' and '.',
/// not empty and not starting with '.' (so neither "." nor ".." nor a hidden folder).
bool is_plain_name(const std::string& name);

/// Reads, validates and resolves a scene. The registry searches the scene's
/// "plugin_path" first, then `extra_search_dirs` (normally the default search path).
/// @throw IoError (unreadable file), SceneValidationError (every problem found),
///        SceneError (bad JSON syntax or a number beyond a double, with line and column).
Scene load_scene(const std::filesystem::path& file,
                 const std::vector<std::filesystem::path>& extra_search_dirs =
                     PluginRegistry::default_search_dirs());

/// load_scene's work on text already read: `file` (made absolute) names the scene in
/// messages, resolves relative paths and gives the default name; it need not exist.
/// Reads nothing but the plugins and the files the scene names; writes nothing (the
/// fuzz target in tests/fuzz feeds it arbitrary text).
/// @throw SceneValidationError, SceneError as load_scene.
Scene parse_scene(const std::string& text, const std::filesystem::path& file,
                  const std::vector<std::filesystem::path>& extra_search_dirs =
                      PluginRegistry::default_search_dirs());

}  // namespace shellflow::runtime
