// ply_writer: the binary file read back with a small independent reader.
#include "shellflow/ply_writer/ply_writer.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "mesh_writer_fixture.hpp"

namespace shellflow::mesh_output::testing {
namespace {

struct PlyFile {
  std::vector<std::string> header;  ///< lines up to and without "end_header"
  std::vector<float> vertices;      ///< 6 per vertex
  std::vector<std::int32_t> faces;  ///< 3 per face
};

/// Reads exactly what ply_writer promises (and fails the test on anything else).
PlyFile read_ply(std::istream& in) {
  PlyFile ply;
  std::string line;
  size_t vertex_count = 0, face_count = 0;
  while (std::getline(in, line) && line != "end_header") {
    ply.header.push_back(line);
    if (line.rfind("element vertex ", 0) == 0) vertex_count = std::stoul(line.substr(15));
    if (line.rfind("element face ", 0) == 0) face_count = std::stoul(line.substr(13));
  }
  auto read_u32 = [&]() {
    unsigned char b[4];
    in.read(reinterpret_cast<char*>(b), 4);
    return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
           static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
  };
  for (size_t i = 0; i < 6 * vertex_count; ++i) {
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
  EXPECT_EQ(in.peek(), std::char_traits<char>::eof()) << "bytes after the last face";
  return ply;
}

TEST_F(MeshWriterTest, PlyHoldsPositionsVelocitiesAndFacesToFloatPrecision) {
  const std::vector<sdk::ShellSurface> shells = {known_shell("solids/cup")};
  ply_writer::PlyWriter writer(nlohmann::json::object(), {});
  writer.begin(run_info());
  writer.write_frame({12, 0.5, shells, nullptr});
  std::ifstream in(m_out / "meshes" / "solids_cup_0012.ply", std::ios::binary);
  ASSERT_TRUE(in);
  const auto ply = read_ply(in);
  const auto& s = shells[0];

  ASSERT_GE(ply.header.size(), 3u);
  EXPECT_EQ(ply.header[0], "ply");
  EXPECT_EQ(ply.header[1], "format binary_little_endian 1.0");
  const std::vector<std::string> properties = {"element vertex " + std::to_string(s.node_count()),
                                               "property float x",
                                               "property float y",
                                               "property float z",
                                               "property float vx",
                                               "property float vy",
                                               "property float vz",
                                               "element face " + std::to_string(s.triangle_count()),
                                               "property list uchar int vertex_indices"};
  const std::vector<std::string> tail(ply.header.end() - 9, ply.header.end());
  EXPECT_EQ(tail, properties);

  ASSERT_EQ(ply.vertices.size(), static_cast<size_t>(6 * s.node_count()));
  // Each value is the double rounded to float: exact equality with float(x).
  for (int i = 0; i < s.node_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(ply.vertices[6 * i + c], static_cast<float>(s.positions(i, c)));
      EXPECT_EQ(ply.vertices[6 * i + 3 + c], static_cast<float>(s.velocities(i, c)));
    }
  ASSERT_EQ(ply.faces.size(), static_cast<size_t>(3 * s.triangle_count()));
  for (int t = 0; t < s.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(ply.faces[3 * t + c], (*s.triangles)(t, c));
}

TEST(WritePly, MissingVelocitiesAreWrittenAsZero) {
  auto s = known_shell("still");
  s.velocities.resize(0, 3);
  std::stringstream bytes;
  ply_writer::write_ply(bytes, s, 0, 0.0);
  const auto ply = read_ply(bytes);
  ASSERT_EQ(ply.vertices.size(), static_cast<size_t>(6 * s.node_count()));
  for (int i = 0; i < s.node_count(); ++i) {
    EXPECT_EQ(ply.vertices[6 * i], static_cast<float>(s.positions(i, 0)));
    EXPECT_EQ(ply.vertices[6 * i + 4], 0.0f);
  }
}

}  // namespace
}  // namespace shellflow::mesh_output::testing
