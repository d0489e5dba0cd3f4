#pragma once
// The "preview_writer" writer: `<out_dir>/<folder>/<scene>_<frame:04d>.png` per written
// frame, rendered by PreviewRenderer (camera, smoke absorption, colours, field names and
// walls from params; which wall is the floor from the scene's gravity).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "shellflow/preview_writer/preview_renderer.hpp"
#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::preview_writer {

/// `<scene>_<frame, 4 digits at least>.png`.
std::string preview_file_name(const std::string& scene_name, int frame);

/// Params (validated against PreviewWriter::schema(), defaults filled) → settings.
/// @throw ConfigError naming the parameter for what the schema cannot check.
PreviewSettings preview_settings_from_json(const nlohmann::json& params);
/// The same, with `down` (which wall is the floor) from the scene's gravity, or the
/// camera's down (−up) when the scene has none.
PreviewSettings preview_settings_from_json(const nlohmann::json& params,
                                           const sdk::Context& context);

class PreviewWriter final : public sdk::Writer {
 public:
  static sdk::Schema schema();
  PreviewWriter(const nlohmann::json& params, const sdk::Context& context);

  /// Creates `<out_dir>/<folder>`. @throw IoError naming the folder.
  void begin(const sdk::RunInfo& info) override;
  /// @throw IoError naming the file.
  void write_frame(const sdk::FrameView& frame) override;

  const std::filesystem::path& folder() const { return m_folder; }
  const PreviewRenderer& renderer() const { return m_renderer; }

 private:
  std::string m_folder_name;
  int m_every = 1;
  PreviewRenderer m_renderer;
  std::string m_scene_name;
  std::filesystem::path m_folder;
};

}  // namespace shellflow::preview_writer
