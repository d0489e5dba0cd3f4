#pragma once
// A small independent reader of the binary little-endian PLY files the liquid_writer
// writes: vertex properties all float (any names), optionally faces as "list uchar int".
// It fails the test on anything else.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <istream>
#include <string>
#include <vector>

namespace shellflow::liquid_writer::testing {

struct PlyFile {
  std::vector<std::string> header;      ///< lines up to and without "end_header"
  std::vector<std::string> properties;  ///< vertex property names, in order
  std::vector<float> vertices;          ///< properties.size() per vertex
  std::vector<std::int32_t> faces;      ///< 3 per face
  size_t vertex_count = 0;
  float value(size_t vertex, const std::string& property) const {
    for (size_t p = 0; p < properties.size(); ++p)
      if (properties[p] == property) return vertices[vertex * properties.size() + p];
    ADD_FAILURE() << "no vertex property " << property;
    return 0.0f;
  }
};

inline PlyFile read_ply(std::istream& in) {
  PlyFile ply;
  std::string line, element;
  size_t face_count = 0;
  std::getline(in, line);
  EXPECT_EQ(line, "ply");
  while (std::getline(in, line) && line != "end_header") {
    ply.header.push_back(line);
    if (line.rfind("element vertex ", 0) == 0) {
      ply.vertex_count = std::stoul(line.substr(15));
      element = "vertex";
    } else if (line.rfind("element face ", 0) == 0) {
      face_count = std::stoul(line.substr(13));
      element = "face";
    } else if (line.rfind("property float ", 0) == 0) {
      EXPECT_EQ(element, "vertex") << line;
      ply.properties.push_back(line.substr(15));
    } else if (line.rfind("property ", 0) == 0) {
      EXPECT_EQ(line, "property list uchar int vertex_indices");
    } else if (line.rfind("format ", 0) == 0) {
      EXPECT_EQ(line, "format binary_little_endian 1.0");
    }
  }
  const auto read_u32 = [&]() {
    unsigned char b[4];
    in.read(reinterpret_cast<char*>(b), 4);
    return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
           static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
  };
  for (size_t i = 0; i < ply.properties.size() * ply.vertex_count; ++i) {
    const std::uint32_t bits = read_u32();
    float f;
    std::memcpy(&f, &bits, 4);
    ply.vertices.push_back(f);
  }
  for (size_t t = 0; t < face_count; ++t) {
    char corners = 0;
    in.read(&corners, 1);
    EXPECT_EQ(corners, 3);
    for (int c = 0; c < 3; ++c) ply.faces.push_back(static_cast<std::int32_t>(read_u32()));
  }
  EXPECT_TRUE(in.good()) << "file shorter than its header says";
  EXPECT_EQ(in.peek(), std::char_traits<char>::eof()) << "bytes after the last element";
  return ply;
}

}  // namespace shellflow::liquid_writer::testing
