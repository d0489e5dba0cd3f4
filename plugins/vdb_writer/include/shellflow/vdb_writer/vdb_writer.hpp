#pragma once
// The "vdb_writer" writer: `<out_dir>/<folder>/<scene>_<frame:04d>.vdb` per written frame
// with every grid field of the fluid (see vdb_frame.hpp for the mapping). A scene without
// a fluid writes nothing (shells go to obj_writer / ply_writer).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/writer.hpp"
#include "shellflow/vdb_writer/vdb_frame.hpp"

namespace shellflow::vdb_writer {

/// `<scene>_<frame, 4 digits at least>.vdb`.
std::string vdb_file_name(const std::string& scene_name, int frame);

class VdbWriter final : public sdk::Writer {
 public:
  static sdk::Schema schema();
  VdbWriter(const nlohmann::json& params, const sdk::Context& context);

  /// Creates `<out_dir>/<folder>`. @throw IoError naming the folder.
  void begin(const sdk::RunInfo& info) override;
  /// @throw IoError naming the file.
  void write_frame(const sdk::FrameView& frame) override;

  const std::filesystem::path& folder() const { return m_folder; }
  const VdbOptions& options() const { return m_options; }

 private:
  std::string m_folder_name;
  int m_every = 1;
  VdbOptions m_options;
  std::string m_scene_name;
  std::filesystem::path m_folder;
};

}  // namespace shellflow::vdb_writer
