// Meshes from the files DCC tools write ("type": "file"): STL (ASCII and binary), PLY and
// glTF through assimp, OBJ through load_obj. A closed tetrahedron must come back closed
// (corners joined: every edge in two triangles) and encloses its known volume; bad files are
// refused naming the file and the vertex.
#include "shellflow/geometry/mesh_import.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scratch_folder.hpp"
#include "shellflow/geometry/mesh_checks.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::geometry {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Severity = MeshCheckSeverity;

constexpr MeshCheckPolicy kAllErrors{Severity::Error, Severity::Error, Severity::Error};
constexpr MeshCheckPolicy kAllWarnings{Severity::Warning, Severity::Warning, Severity::Warning};

// The tetrahedron with corners O, 2X, 3Y, 4Z, outward faces: volume 2·3·4/6 = 4.
const std::array<std::array<float, 3>, 4> kCorners{{{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0, 0, 4}}};
const std::array<std::array<int, 3>, 4> kFaces{{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};

/// Signed enclosed volume Σ (a · (b × c)) / 6: exact for a closed, consistently oriented mesh.
double enclosed_volume(const SurfaceMesh& m) {
  double v = 0.0;
  for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
    const Eigen::Vector3d a = m.positions.row(m.triangles(t, 0));
    const Eigen::Vector3d b = m.positions.row(m.triangles(t, 1));
    const Eigen::Vector3d c = m.positions.row(m.triangles(t, 2));
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

class MeshImport : public shellflow::testing::ScratchFolder {
 protected:
  /// The tetrahedron as ASCII STL; `corner_text` replaces one corner's coordinates.
  fs::path ascii_stl(const std::string& name, int bad_facet = -1, int bad_corner = -1,
                     const std::string& corner_text = "") const {
    std::string s = "solid tetra\n";
    for (int f = 0; f < 4; ++f) {
      s += "facet normal 0 0 0\nouter loop\n";
      for (int c = 0; c < 3; ++c) {
        const auto& p = kCorners[static_cast<size_t>(kFaces[f][c])];
        s +=
            "vertex " +
            (f == bad_facet && c == bad_corner
                 ? corner_text
                 : std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2])) +
            "\n";
      }
      s += "endloop\nendfacet\n";
    }
    return write(name, s + "endsolid tetra\n");
  }
  std::string load_error(const fs::path& file) const {
    try {
      load_mesh_file(file);
    } catch (const IoError& e) {
      EXPECT_THAT(e.what(), HasSubstr(file.string()));
      return e.what();
    }
    ADD_FAILURE() << "read without error: " << file;
    return "";
  }
};

TEST_F(MeshImport, AsciiStlTetrahedronComesBackClosedWithItsVolume) {
  const auto mesh = load_mesh_file(ascii_stl("tetra.stl"));
  // STL stores 12 corners apart; joined by position they are the 4 corners again.
  EXPECT_EQ(mesh.positions.rows(), 4);
  EXPECT_EQ(mesh.triangles.rows(), 4);
  // Closed and 2-manifold: no defect at all (every edge in exactly two triangles).
  const auto report = check_mesh(mesh, kAllErrors, "/mesh");
  EXPECT_EQ(report.degenerate_triangles + report.non_manifold_edges + report.unreferenced_vertices,
            0);
  // Orientation kept: the enclosed volume is +4 to the file's float precision (the
  // coordinates are small integers: exact).
  EXPECT_DOUBLE_EQ(enclosed_volume(mesh), 4.0);
}

TEST_F(MeshImport, BinaryStlReadsTheSameAsAscii) {
  std::string bytes(80, ' ');  // header
  const uint32_t count = 4;
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& face : kFaces) {
    const std::array<float, 3> normal{0, 0, 0};
    bytes.append(reinterpret_cast<const char*>(normal.data()), 12);
    for (const int c : face)
      bytes.append(reinterpret_cast<const char*>(kCorners[static_cast<size_t>(c)].data()), 12);
    bytes.append(2, '\0');  // attribute byte count
  }
  const auto mesh = load_mesh_file(write("tetra.stl", bytes));
  EXPECT_EQ(mesh.positions.rows(), 4);
  EXPECT_EQ(mesh.triangles.rows(), 4);
  EXPECT_DOUBLE_EQ(enclosed_volume(mesh), 4.0);
}

TEST_F(MeshImport, PlyKeepsItsVertexNumbersAndCountsAnUnusedOne) {
  // A unit square as one quad (triangulated into two) and a fifth vertex no face uses.
  const auto file = write("square.ply",
                          "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\n"
                          "property list uchar int vertex_indices\nend_header\n"
                          "0 0 0\n1 0 0\n1 1 0\n0 1 0\n7 7 7\n4 0 1 2 3\n");
  const auto mesh = load_mesh_file(file);
  EXPECT_EQ(mesh.triangles.rows(), 2);
  EXPECT_EQ(mesh.positions.rows(), 4);
  // Its area is the quad's, and it faces +z (counter-clockwise in the file).
  Eigen::Vector3d area = Eigen::Vector3d::Zero();
  for (Eigen::Index t = 0; t < 2; ++t) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(t, 0));
    const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(t, 1));
    const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(t, 2));
    area += 0.5 * (b - a).cross(c - a);
  }
  EXPECT_LT((area - Eigen::Vector3d(0, 0, 1)).norm(), 1e-15);
  const auto report = check_mesh(mesh, kAllWarnings, "/mesh", "sheet");
  EXPECT_EQ(report.unreferenced_vertices, 1);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_THAT(report.warnings[0], HasSubstr("(the first: vertex 5)"));
}

/// Base64 of `bytes` (RFC 4648), for a glTF's embedded buffer.
std::string base64(const std::string& bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t n = static_cast<uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= static_cast<uint8_t>(bytes[i + 2]);
    out += kDigits[(n >> 18) & 63];
    out += kDigits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kDigits[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

TEST_F(MeshImport, GltfTetrahedronIsPlacedByItsNodeTransform) {
  std::string buffer;
  for (const auto& p : kCorners) buffer.append(reinterpret_cast<const char*>(p.data()), 12);
  for (const auto& face : kFaces)
    for (const int c : face) {
      const auto index = static_cast<uint16_t>(c);
      buffer.append(reinterpret_cast<const char*>(&index), 2);
    }
  const std::string gltf = R"({
    "asset": {"version": "2.0"},
    "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "translation": [10, 20, 30]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
    "buffers": [{"byteLength": 72,
                 "uri": "data:application/octet-stream;base64,)" +
                           base64(buffer) + R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 48, "byteLength": 24}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
       "min": [0, 0, 0], "max": [2, 3, 4]},
      {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}]})";
  const auto mesh = load_mesh_file(write("tetra.gltf", gltf));
  ASSERT_EQ(mesh.positions.rows(), 4);
  EXPECT_EQ(mesh.triangles.rows(), 4);
  // The node's translation moved every corner; the shape and its volume are unchanged.
  EXPECT_EQ(Eigen::Vector3d(mesh.positions.colwise().minCoeff()), Eigen::Vector3d(10, 20, 30));
  EXPECT_EQ(Eigen::Vector3d(mesh.positions.colwise().maxCoeff()), Eigen::Vector3d(12, 23, 34));
  EXPECT_NEAR(enclosed_volume(mesh), 4.0, 1e-12 * 34 * 34 * 34);  // round-off of the shift
}

TEST_F(MeshImport, NonFiniteCornerNamesTheFileVertexAndTriangle) {
  // Facet 2, corner 2 (vertex 5 of the STL's 12) reads "nan": assimp passes it on as NaN.
  const std::string e = load_error(ascii_stl("nan.stl", 1, 1, "nan 1 0"));
  EXPECT_THAT(e,
              HasSubstr("vertex 5 (triangle 2, corner 2) has a non-finite coordinate (x = nan)"));
  EXPECT_THAT(load_error(ascii_stl("inf.stl", 3, 0, "2 inf 0")),
              HasSubstr("vertex 10 (triangle 4, corner 1) has a non-finite coordinate (y = inf)"));
}

TEST_F(MeshImport, UnknownFormatMissingFileAndGarbageAreRefusedNamingTheFile) {
  EXPECT_THAT(load_error(write("mesh.txt", "0 0 0\n")),
              HasSubstr("'.txt' is not a mesh format shellflow reads; use .obj, .stl, .ply"));
  EXPECT_THAT(load_error(m_dir / "absent.stl"), HasSubstr("no such file"));
  EXPECT_THAT(load_error(write("garbage.stl", "garbage")), HasSubstr("cannot read the mesh file"));
  // A PLY of points only: nothing a shell can be made of.
  load_error(write("points.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
                   "y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n"));
}

TEST_F(MeshImport, SceneFormReadsEveryFormatAndPutsErrorsAtTheFileParameter) {
  const auto stl = ascii_stl("tetra.stl");
  const auto from_file = make_mesh({{"type", "file"}, {"file", stl.string()}}, "/solids/0/mesh");
  EXPECT_EQ(from_file.positions.rows(), 4);
  // An OBJ through "file" is load_obj's, with the lines of its vertices in errors.
  const auto obj = write("bad.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  try {
    make_mesh({{"type", "file"}, {"file", obj.string()}}, "/solids/0/mesh");
    FAIL() << "read a NaN";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/mesh/file");
    EXPECT_THAT(e.what(), HasSubstr(":3: vertex 3 has a non-finite coordinate"));
  }
  try {
    make_mesh({{"type", "file"}, {"file", ascii_stl("nan.stl", 0, 0, "0 nan 0").string()}},
              "/mesh");
    FAIL() << "read a NaN";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/mesh/file");
    EXPECT_THAT(e.what(), HasSubstr("vertex 1 (triangle 1, corner 1)"));
  }
  try {
    make_mesh({{"type", "file"}}, "/mesh");
    FAIL() << "no file";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/mesh/file");
  }
  // The formats named in the README are among those read.
  const auto extensions = mesh_file_extensions();
  for (const char* ext : {".obj", ".stl", ".ply", ".gltf", ".glb", ".fbx", ".dae"})
    EXPECT_THAT(extensions, ::testing::Contains(std::string(ext))) << ext;
}

}  // namespace
}  // namespace shellflow::geometry
