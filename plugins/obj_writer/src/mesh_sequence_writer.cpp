#include "shellflow/mesh_output/mesh_sequence_writer.hpp"

#include <algorithm>
#include <cstdio>
#include <system_error>

#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::mesh_output {

sdk::Schema mesh_sequence_schema(const std::string& doc) {
  using sdk::Schema;
  return Schema::object(doc)
      .field("folder",
             Schema::string("meshes").subfolder().doc("sub-folder of the run's output folder"))
      .field("every",
             Schema::integer(1).min(1).doc("write every n-th frame (frame 0, n, 2n, ...)"));
}

std::string frame_file_name(const std::string& shell_name, int frame,
                            const std::string& extension) {
  std::string stem = shell_name;
  std::replace(stem.begin(), stem.end(), '/', '_');
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return stem + "_" + number + "." + extension;
}

MeshSequenceWriter::MeshSequenceWriter(const nlohmann::json& params, std::string extension)
    : m_folder_name(params.value("folder", std::string("meshes"))),
      m_extension(std::move(extension)),
      m_every(params.value("every", 1)) {
  if (m_every < 1) throw ConfigError("/every", "must be at least 1");
  sdk::check_subfolder(m_folder_name, "/folder");
}

void MeshSequenceWriter::begin(const sdk::RunInfo& info) {
  m_folder = sdk::make_output_subfolder(info, m_folder_name);
}

void MeshSequenceWriter::write_frame(const sdk::FrameView& frame) {
  if (m_folder.empty())
    throw Error("mesh writer: write_frame() called before begin() (a runtime bug)");
  if (frame.frame % m_every != 0) return;
  for (const auto& shell : frame.shells)
    sdk::write_file_atomically(m_folder / frame_file_name(shell.name, frame.frame, m_extension),
                          [&](std::ostream& out) { write_shell(out, shell, frame); });
}

}  // namespace shellflow::mesh_output
