// mass_spring_cloth refuses every mesh defect (see its constructor for why): a zero-area
// triangle, a vertex no triangle uses and an edge of more than two triangles, each named by
// the scene file, the JSON path, the OBJ file, the vertices and their lines.
#include "../mesh_check_scenes.hpp"

namespace shellflow::cloth {
namespace {

using ::testing::HasSubstr;
using Fixture = shellflow::testing::MeshCheckScene;
namespace td = shellflow::testing;

constexpr const char* kCloth =
    R"({"plugin": "mass_spring_cloth", "mesh": {"type": "obj", "file": "mesh.obj"}})";

class ClothMeshChecks : public Fixture {};

TEST_F(ClothMeshChecks, ACleanObjConstructs) {
  const auto plugins = construct(td::kCleanObj, kCloth);
  ASSERT_EQ(plugins.solids.size(), 1u);
  EXPECT_EQ(plugins.solids[0]->surfaces()[0].node_count(), 4);
  EXPECT_THAT(log(), ::testing::Not(HasSubstr("mesh.obj")));
}

TEST_F(ClothMeshChecks, EdgeOfThreeTrianglesIsAnErrorNamingItsVertices) {
  const auto e = refusal(td::kNonManifoldObj, kCloth);
  EXPECT_EQ(e.json_path(), "/solids/0/mesh/file");
  EXPECT_THAT(e.what(),
              HasSubstr("the edge between vertices 1 (line 1) and 2 (line 2), in 3 triangles"));
}

TEST_F(ClothMeshChecks, ZeroAreaTriangleIsAnError) {
  const auto e = refusal(td::kZeroAreaObj, kCloth);
  EXPECT_EQ(e.json_path(), "/solids/0/mesh/file");
  EXPECT_THAT(e.what(), HasSubstr("1 triangle has zero area"));
  EXPECT_THAT(e.what(), HasSubstr("vertices 2 (line 2), 5 (line 9) and 6 (line 10)"));
}

TEST_F(ClothMeshChecks, UnreferencedVertexIsAnErrorSincePinsCountNodes) {
  const auto e = refusal(td::kLooseVertexObj, kCloth);
  EXPECT_EQ(e.json_path(), "/solids/0/mesh/file");
  EXPECT_THAT(e.what(),
              HasSubstr("1 vertex is used by no triangle (the first: vertex 5 (line 9))"));
}

}  // namespace
}  // namespace shellflow::cloth
