#include "shellflow/obj_writer/obj_writer.hpp"

#include <algorithm>
#include <charconv>
#include <string>

namespace shellflow::obj_writer {

namespace {

void append_number(std::string& text, double value) {
  char buffer[32];
  // Shortest form that reads back as the same double (std::to_chars round-trip guarantee).
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  text.append(buffer, result.ptr);
}

void append_number(std::string& text, int value) {
  char buffer[16];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  text.append(buffer, result.ptr);
}

}  // namespace

void write_obj(std::ostream& out, const sdk::ShellSurface& shell, int frame, double time) {
  std::string name = shell.name;  // a line break would end the comment line
  std::replace_if(
      name.begin(), name.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  std::string text =
      "# shellflow obj_writer: mesh " + name + ", frame " + std::to_string(frame) + ", t = ";
  append_number(text, time);
  text += " s\n";
  for (Eigen::Index i = 0; i < shell.positions.rows(); ++i) {
    text += 'v';
    for (int c = 0; c < 3; ++c) {
      text += ' ';
      append_number(text, shell.positions(i, c));
    }
    text += '\n';
  }
  if (shell.triangles) {
    const auto& triangles = *shell.triangles;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
      text += 'f';
      for (int c = 0; c < 3; ++c) {
        text += ' ';
        append_number(text, triangles(t, c) + 1);
      }
      text += '\n';
    }
  }
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

sdk::Schema ObjWriter::schema() {
  return mesh_output::mesh_sequence_schema(
      "one Wavefront OBJ file per shell per frame: <folder>/<shell>_<frame>.obj");
}

ObjWriter::ObjWriter(const nlohmann::json& params, const sdk::Context& /*context*/)
    : MeshSequenceWriter(params, "obj") {}

void ObjWriter::write_shell(std::ostream& out, const sdk::ShellSurface& shell,
                            const sdk::FrameView& frame) const {
  write_obj(out, shell, frame.frame, frame.time);
}

}  // namespace shellflow::obj_writer
