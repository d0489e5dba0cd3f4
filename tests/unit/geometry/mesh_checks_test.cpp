// Meshes checked when read: non-finite OBJ coordinates (file, line, vertex), and the
// defects check_mesh() reports as errors or warnings with counts as a solid's policy says.
#include "shellflow/geometry/mesh_checks.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::geometry {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Severity = MeshCheckSeverity;

constexpr MeshCheckPolicy kAllErrors{Severity::Error, Severity::Error, Severity::Error};
constexpr MeshCheckPolicy kAllWarnings{Severity::Warning, Severity::Warning, Severity::Warning};

// A unit square as two triangles (lines 1-4), then whatever a test appends.
constexpr const char* kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";

class MeshChecks : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = fs::temp_directory_path() / ("shellflow_mesh_checks_" + std::string(info->name()) +
                                         "_" + std::to_string(::getpid()));
    fs::create_directories(m_dir);
  }
  void TearDown() override { fs::remove_all(m_dir); }
  fs::path obj(const std::string& text, const std::string& name = "mesh.obj") {
    const auto file = m_dir / name;
    std::ofstream(file) << text;
    return file;
  }
  /// The IoError load_obj throws for `text` (fails the test if it reads it).
  std::string load_error(const std::string& text) {
    const auto file = obj(text);
    try {
      load_obj(file);
    } catch (const IoError& e) {
      EXPECT_THAT(e.what(), HasSubstr(file.string()));
      return e.what();
    }
    ADD_FAILURE() << "read without error:\n" << text;
    return "";
  }
  /// The ConfigError check_mesh throws (fails the test if it passes).
  static ConfigError check_error(const SurfaceMesh& mesh, const std::string& json_path = "/mesh") {
    try {
      check_mesh(mesh, kAllErrors, json_path);
    } catch (const ConfigError& e) {
      return e;
    }
    ADD_FAILURE() << "the mesh passed";
    return ConfigError("", "");
  }

  fs::path m_dir;
};

SurfaceMesh mesh_of(std::initializer_list<std::array<double, 3>> nodes,
                    std::initializer_list<std::array<int, 3>> triangles) {
  SurfaceMesh m;
  m.positions.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  Eigen::Index i = 0;
  for (const auto& p : nodes) m.positions.row(i++) << p[0], p[1], p[2];
  m.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  i = 0;
  for (const auto& t : triangles) m.triangles.row(i++) << t[0], t[1], t[2];
  return m;
}

// Non-finite and unreadable coordinates -------------------------------------------------

TEST_F(MeshChecks, NanVertexNamesFileLineAndVertex) {
  // tinyobjloader alone reads "nan" as 0: the mesh would be simulated with a wrong node.
  const auto what = load_error("# comment\nv 0 0 0\nv 1 0 0\nv 1 nan 0\nf 1 2 3\n");
  EXPECT_THAT(what, HasSubstr("mesh.obj:4: vertex 3 has a non-finite coordinate (y = nan)"));
}

TEST_F(MeshChecks, InfiniteAndOverflowingVerticesAreRefusedToo) {
  EXPECT_THAT(load_error("v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"),
              HasSubstr("mesh.obj:2: vertex 2 has a non-finite coordinate (x = inf)"));
  EXPECT_THAT(load_error("v 0 0 0\nvn 0 0 1\nv 1 0 0\n  v 0 1 -1e400\nf 1 2 3\n"),
              HasSubstr("mesh.obj:4: vertex 3 has a non-finite coordinate (z = -1e400)"));
}

TEST_F(MeshChecks, CoordinateThatIsNotANumberOrMissingIsRefused) {
  EXPECT_THAT(load_error("v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n"),
              HasSubstr("mesh.obj:2: vertex 2: its y coordinate 'abc' is not a number"));
  EXPECT_THAT(load_error("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"),
              HasSubstr("mesh.obj:2: vertex 2 has 2 coordinates"));
}

TEST_F(MeshChecks, FaceIndexOutOfRangeAndNoFacesStayErrors) {
  EXPECT_THAT(load_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"),
              HasSubstr("face refers to vertex 7, but the file has 3 vertices"));
  EXPECT_THAT(load_error("v 0 0 0\nv 1 0 0\n"), HasSubstr("holds no faces"));
}

TEST_F(MeshChecks, MakeMeshPutsTheObjErrorAtTheFileParameter) {
  const auto file = obj("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  try {
    make_mesh({{"type", "obj"}, {"file", file.string()}}, "/bodies/2/mesh");
    FAIL() << "read";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/bodies/2/mesh/file");
    EXPECT_THAT(e.what(), HasSubstr(file.string() + ":3: vertex 3"));
  }
}

TEST_F(MeshChecks, ObjVerticesRememberTheirNumberAndLine) {
  // Vertex 3 (line 4) is unused and dropped; the others keep file numbers and lines.
  const auto m = load_obj(obj("v 0 0 0\nv 1 0 0\n\nv 5 5 5\nv 0 1 0\nf 1 2 4\n"));
  ASSERT_TRUE(m.origin);
  EXPECT_EQ(m.origin->vertex_number, (std::vector<int>{1, 2, 4}));
  EXPECT_EQ(m.origin->vertex_line, (std::vector<int>{1, 2, 5}));
  EXPECT_EQ(m.origin->unreferenced_count, 1);
  EXPECT_EQ(m.origin->first_unreferenced, 3);
  EXPECT_EQ(m.origin->first_unreferenced_line, 4);
}

// Degenerate triangles, unreferenced vertices, non-manifold edges -----------------------

TEST_F(MeshChecks, GeneratedMeshesHaveNoDefects) {
  for (const auto& mesh :
       {make_grid(2, 1, 7, 5, GridPattern::Herringbone), make_box({1, 2, 3}, 3),
        make_open_box({1, 1, 1}, 2), make_open_cylinder(0.5, 1, 12, 3, true), make_sphere(1, 2)}) {
    const auto report = check_mesh(mesh, kAllErrors, "/mesh");
    EXPECT_EQ(report.degenerate_triangles, 0);
    EXPECT_EQ(report.unreferenced_vertices, 0);
    EXPECT_EQ(report.non_manifold_edges, 0);
    EXPECT_TRUE(report.warnings.empty());
  }
}

TEST_F(MeshChecks, ZeroAreaTriangleInAnObjNamesItsVerticesAndLines) {
  // Triangle 2 (vertices 2, 5, 6) lies on the x axis: collinear corners.
  const auto file = obj(std::string(kSquare) + "v 2 0 0\nv 3 0 0\nf 2 5 6\n");
  const auto e = check_error(load_obj(file));
  EXPECT_EQ(e.json_path(), "/mesh/file");
  EXPECT_THAT(e.what(), HasSubstr(file.string() + ": 1 triangle has zero area"));
  EXPECT_THAT(e.what(),
              HasSubstr("triangle 2 with vertices 2 (line 2), 5 (line 7) and 6 (line 8)"));
}

TEST_F(MeshChecks, RepeatedCornerIsZeroAreaAndASliverIsNot) {
  // A sliver 1e-6 high on a unit base: thin, but its area is far above round-off.
  const auto sliver = mesh_of({{0, 0, 0}, {1, 0, 0}, {0.5, 1e-6, 0}}, {{0, 1, 2}});
  EXPECT_EQ(check_mesh(sliver, kAllErrors, "/mesh").degenerate_triangles, 0);
  const auto repeated = mesh_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {1, 1, 2}});
  const auto e = check_error(repeated, "/solids/0/mesh");
  EXPECT_EQ(e.json_path(), "/solids/0/mesh");  // a generated mesh: no file
  EXPECT_THAT(e.what(), HasSubstr("triangle 1 with nodes 1, 1 and 2"));
}

TEST_F(MeshChecks, WarningsCountEveryDefectAndKeepTheMesh) {
  // Two zero-area triangles, two unused vertices (lines 5, 6), an edge 1-2 in four
  // triangles and an edge 1-3 in three.
  const auto file =
      obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 7 7 7\nv 8 8 8\nv 0 0 -1\nv 2 0 0\nv 0 2 0\n"
          "f 1 2 3\nf 1 2 4\nf 1 2 7\nf 1 2 8\nf 1 3 9\nf 1 3 4\n");
  const auto mesh = load_obj(file);
  const auto report = check_mesh(mesh, kAllWarnings, "/mesh", "cup");
  EXPECT_EQ(report.degenerate_triangles, 2);  // (1, 2, 8) and (1, 3, 9)
  EXPECT_EQ(report.unreferenced_vertices, 2);
  EXPECT_EQ(report.non_manifold_edges, 2);
  ASSERT_EQ(report.warnings.size(), 3u);
  EXPECT_THAT(report.warnings[0], HasSubstr("2 triangles have zero area"));
  EXPECT_THAT(report.warnings[1],
              HasSubstr("2 vertices are used by no triangle (the first: vertex 5 (line 5))"));
  EXPECT_THAT(report.warnings[2], HasSubstr("2 edges are shared by more than two triangles"));
}

TEST_F(MeshChecks, NonManifoldEdgeIsAnErrorNamingTheEdgesVertices) {
  // Three fins on the edge between vertices 1 and 2.
  const auto file =
      obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  MeshCheckPolicy policy = kAllWarnings;
  policy.non_manifold_edges = Severity::Error;
  try {
    check_mesh(load_obj(file), policy, "/mesh");
    FAIL() << "passed";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/mesh/file");
    EXPECT_THAT(e.what(), HasSubstr(file.string()));
    EXPECT_THAT(e.what(),
                HasSubstr("the edge between vertices 1 (line 1) and 2 (line 2), in 3 triangles"));
  }
}

TEST_F(MeshChecks, UnreferencedVerticesAreAnErrorWhereThePolicySaysSo) {
  const auto file = obj(std::string(kSquare) + "v 5 5 5\n");
  const auto e = check_error(load_obj(file));
  EXPECT_THAT(e.what(),
              HasSubstr("1 vertex is used by no triangle (the first: vertex 5 (line 7))"));
  // The generated form: a node no triangle uses.
  const auto loose = mesh_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {3, 3, 3}}, {{0, 1, 2}});
  EXPECT_THAT(check_error(loose).what(), HasSubstr("(the first: node 3)"));
}

TEST_F(MeshChecks, NonFinitePositionMissingTrianglesAndBadIndicesAreAlwaysErrors) {
  auto grid = make_grid(1e300, 1, 2, 2, GridPattern::Regular);
  apply_transform(transform_from_json({{"scale", 1e10}}), grid);  // 1e310 overflows
  try {
    check_mesh(grid, kAllWarnings, "/mesh");
    FAIL() << "passed";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/mesh");
    EXPECT_THAT(e.what(), HasSubstr("node 0 is at (-inf"));
  }
  EXPECT_THROW(check_mesh(mesh_of({{0, 0, 0}}, {}), kAllWarnings, "/mesh"), ConfigError);
  const auto bad_index = mesh_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}});
  try {
    check_mesh(bad_index, kAllWarnings, "/mesh");
    FAIL() << "passed";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("triangle 0 refers to node 3, but the mesh has 3 nodes"));
  }
}

}  // namespace
}  // namespace shellflow::geometry
