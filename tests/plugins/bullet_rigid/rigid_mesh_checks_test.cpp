// bullet_rigid: a zero-area triangle is an error (GImpact's contact plane of it would be
// NaN); an edge of more than two triangles and unused vertices are warnings with counts.
#include "../mesh_check_scenes.hpp"

namespace shellflow::bullet_rigid {
namespace {

using ::testing::HasSubstr;
using Fixture = shellflow::testing::MeshCheckScene;
namespace td = shellflow::testing;

constexpr const char* kRigid = R"({"plugin": "bullet_rigid", "name": "rb", "bodies": [
    {"name": "ok", "mesh": {"type": "sphere", "subdivisions": 1}},
    {"name": "cup", "mesh": {"type": "obj", "file": "mesh.obj"}, "transform": {"translate": [3, 0, 0]}}]})";

class RigidMeshChecks : public Fixture {};

TEST_F(RigidMeshChecks, ZeroAreaTriangleIsAnErrorAtTheBodysMesh) {
  const auto e = refusal(td::kZeroAreaObj, kRigid);
  EXPECT_EQ(e.json_path(), "/solids/0/bodies/1/mesh/file");
  EXPECT_THAT(e.what(), HasSubstr("1 triangle has zero area (the first: triangle 4 with vertices 2 "
                                  "(line 2), 5 (line 9) and 6 (line 10))"));
}

TEST_F(RigidMeshChecks, NonManifoldEdgeAndLooseVertexAreWarnings) {
  for (const auto& [obj, warning] :
       {std::pair{td::kNonManifoldObj, "1 edge is shared by more than two triangles"},
        std::pair{td::kLooseVertexObj, "1 vertex is used by no triangle"}}) {
    const auto plugins = construct(obj, kRigid);
    ASSERT_EQ(plugins.solids.size(), 1u);
    EXPECT_EQ(plugins.solids[0]->surfaces().size(), 2u);
    EXPECT_THAT(log(),
                HasSubstr("body 'cup': /bodies/1/mesh: " + obj_file().string() + ": " + warning));
  }
}

}  // namespace
}  // namespace shellflow::bullet_rigid
