#pragma once
// Base of the per-frame mesh writers (obj_writer, ply_writer): parameters "folder" and
// "every", one file `<out_dir>/<folder>/<shell name, '/' → '_'>_<frame:04d>.<ext>` per
// shell per written frame, each written atomically.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::mesh_output {

/// The parameters every mesh sequence writer shares; `doc` describes the format.
sdk::Schema mesh_sequence_schema(const std::string& doc);

/// `<shell name with '/' replaced by '_'>_<frame, 4 digits at least>.<extension>`.
std::string frame_file_name(const std::string& shell_name, int frame, const std::string& extension);

class MeshSequenceWriter : public sdk::Writer {
 public:
  /// Creates `<out_dir>/<folder>`. @throw IoError naming the folder.
  void begin(const sdk::RunInfo& info) override;
  /// Writes every shell of frames whose number is a multiple of "every".
  /// @throw IoError naming the file.
  void write_frame(const sdk::FrameView& frame) override;

  const std::filesystem::path& folder() const { return m_folder; }
  int every() const { return m_every; }

 protected:
  /// `params` validated against mesh_sequence_schema(); `extension` without the dot.
  MeshSequenceWriter(const nlohmann::json& params, std::string extension);
  /// One shell of one frame in this writer's format.
  virtual void write_shell(std::ostream& out, const sdk::ShellSurface& shell,
                           const sdk::FrameView& frame) const = 0;

 private:
  std::string m_folder_name;
  std::string m_extension;
  int m_every = 1;
  std::filesystem::path m_folder;
};

}  // namespace shellflow::mesh_output
