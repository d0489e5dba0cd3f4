// kinematic_shell copes with every mesh defect (see its constructor for why): each is a
// warning with its count, naming the OBJ file, and the shell is built as the file says.
// A non-finite coordinate stays an error, with the file, line and vertex.
#include "../mesh_check_scenes.hpp"

namespace shellflow::kinematic_shell {
namespace {

using ::testing::HasSubstr;
using Fixture = shellflow::testing::MeshCheckScene;
namespace td = shellflow::testing;

constexpr const char* kShell =
    R"({"plugin": "kinematic_shell", "name": "lid", "mesh": {"type": "obj", "file": "mesh.obj"}})";

class KinematicMeshChecks : public Fixture {};

TEST_F(KinematicMeshChecks, DefectsAreWarningsWithCounts) {
  struct Case {
    const char* obj;
    int triangles;
    const char* warning;
  };
  for (const Case& c : {Case{td::kNonManifoldObj, 3, "1 edge is shared by more than two triangles"},
                        Case{td::kZeroAreaObj, 5, "1 triangle has zero area"},
                        Case{td::kLooseVertexObj, 4, "1 vertex is used by no triangle"}}) {
    const auto plugins = construct(c.obj, kShell);
    ASSERT_EQ(plugins.solids.size(), 1u);
    EXPECT_EQ(plugins.solids[0]->surfaces()[0].triangle_count(), c.triangles);
    EXPECT_THAT(log(), HasSubstr("lid: /mesh: " + obj_file().string() + ": " + c.warning));
  }
}

TEST_F(KinematicMeshChecks, NanVertexIsStillAnError) {
  const auto e = refusal("v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 1\nf 1 2 3\nf 1 2 4\n", kShell);
  EXPECT_EQ(e.json_path(), "/solids/0/mesh/file");
  EXPECT_THAT(e.what(), HasSubstr(obj_file().string() +
                                  ":4: vertex 4 has a non-finite coordinate (x = nan)"));
}

}  // namespace
}  // namespace shellflow::kinematic_shell
