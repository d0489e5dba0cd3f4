#include "shellflow/ply_writer/ply_writer.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

namespace shellflow::ply_writer {

namespace {

/// Appends `value` as 4 little-endian bytes whatever the host's byte order.
void put_u32(std::vector<char>& bytes, std::uint32_t value) {
  for (int b = 0; b < 4; ++b) bytes.push_back(static_cast<char>((value >> (8 * b)) & 0xffu));
}

}  // namespace

void put_float(std::vector<char>& bytes, double value) {
  put_u32(bytes, std::bit_cast<std::uint32_t>(static_cast<float>(value)));
}

void write_ply(std::ostream& out, const sdk::ShellSurface& shell, int frame, double time) {
  const Eigen::Index nodes = shell.positions.rows();
  const Eigen::Index triangles = shell.triangles ? shell.triangles->rows() : 0;
  const bool has_velocity = shell.velocities.rows() == nodes && shell.velocities.cols() == 3;
  std::string name = shell.name;  // a line break would end the header's comment line
  std::replace_if(
      name.begin(), name.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');

  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment shellflow ply_writer: mesh " + name +
      ", frame " + std::to_string(frame) + ", t = " + std::to_string(time) + " s\nelement vertex " +
      std::to_string(nodes) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property float vx\nproperty float vy\nproperty float vz\n"
      "element face " +
      std::to_string(triangles) + "\nproperty list uchar int vertex_indices\nend_header\n";
  std::vector<char> bytes(header.begin(), header.end());
  bytes.reserve(bytes.size() + static_cast<size_t>(nodes) * 24 +
                static_cast<size_t>(triangles) * 13);
  for (Eigen::Index i = 0; i < nodes; ++i) {
    for (int c = 0; c < 3; ++c) put_float(bytes, shell.positions(i, c));
    for (int c = 0; c < 3; ++c) put_float(bytes, has_velocity ? shell.velocities(i, c) : 0.0);
  }
  for (Eigen::Index t = 0; t < triangles; ++t) {
    bytes.push_back(3);
    for (int c = 0; c < 3; ++c)
      put_u32(bytes, static_cast<std::uint32_t>((*shell.triangles)(t, c)));
  }
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

sdk::Schema PlyWriter::schema() {
  return mesh_output::mesh_sequence_schema(
      "one binary PLY file per shell per frame with node velocities (vx, vy, vz): "
      "<folder>/<shell>_<frame>.ply");
}

PlyWriter::PlyWriter(const nlohmann::json& params, const sdk::Context& /*context*/)
    : MeshSequenceWriter(params, "ply") {}

void PlyWriter::write_shell(std::ostream& out, const sdk::ShellSurface& shell,
                            const sdk::FrameView& frame) const {
  write_ply(out, shell, frame.frame, frame.time);
}

}  // namespace shellflow::ply_writer
