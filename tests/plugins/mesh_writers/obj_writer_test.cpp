// obj_writer: files read back through tinyobjloader and through strtod, exactly.
#include "shellflow/obj_writer/obj_writer.hpp"

#include <dlfcn.h>
#include <tiny_obj_loader.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "mesh_writer_fixture.hpp"
#include "shellflow/sdk/plugin.hpp"
#include "test_paths.hpp"

namespace shellflow::mesh_output::testing {
namespace {

TEST_F(MeshWriterTest, ObjReadsBackThroughTinyObjLoader) {
  const std::vector<sdk::ShellSurface> shells = {known_shell("solids/cup")};
  obj_writer::ObjWriter writer(nlohmann::json::object(), {});
  writer.begin(run_info());
  writer.write_frame({5, 5 / 24.0, shells, nullptr});
  const auto file = m_out / "meshes" / "solids_cup_0005.obj";
  ASSERT_TRUE(std::filesystem::exists(file));

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warning, error;
  ASSERT_TRUE(tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error, file.c_str()))
      << error;
  const auto& s = shells[0];
  ASSERT_EQ(attrib.vertices.size(), static_cast<size_t>(3 * s.positions.rows()));
  // tinyobjloader (Debian's float build) parses the decimal to double and rounds to float;
  // the decimal is the exact shortest form of the double, so the float is exactly
  // float(x).
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(attrib.vertices[3 * i + c], static_cast<float>(s.positions(i, c)));
  ASSERT_EQ(shapes.size(), 1u);
  ASSERT_EQ(shapes[0].mesh.indices.size(), static_cast<size_t>(3 * s.triangle_count()));
  for (int t = 0; t < s.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(shapes[0].mesh.indices[3 * t + c].vertex_index, (*s.triangles)(t, c));
}

TEST(WriteObj, CoordinatesRoundTripAsDoublesBitForBit) {
  const auto s = known_shell("x");
  std::stringstream text;
  obj_writer::write_obj(text, s, 0, 0.0);
  std::string line;
  Eigen::Index node = 0;
  int faces = 0;
  while (std::getline(text, line)) {
    if (line.rfind("v ", 0) == 0) {
      const char* p = line.c_str() + 2;
      for (int c = 0; c < 3; ++c) {
        char* end = nullptr;
        EXPECT_EQ(std::strtod(p, &end), s.positions(node, c)) << line;  // exact
        p = end;
      }
      ++node;
    } else if (line.rfind("f ", 0) == 0) {
      int a = 0, b = 0, c = 0;
      std::istringstream(line.substr(2)) >> a >> b >> c;
      EXPECT_EQ(a - 1, (*s.triangles)(faces, 0));  // 1-based
      EXPECT_EQ(c - 1, (*s.triangles)(faces, 2));
      ++faces;
    }
  }
  EXPECT_EQ(node, s.positions.rows());
  EXPECT_EQ(faces, s.triangle_count());
}

TEST(ObjWriterPlugin, EntryPointCreatesTheWriter) {
  const auto file =
      std::filesystem::path(shellflow::test_paths::plugin_dir()) / "shellflow_obj_writer.so";
  void* library = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(library, nullptr) << dlerror();
  const auto entry = reinterpret_cast<ShellflowPluginEntry>(dlsym(library, SHELLFLOW_ENTRY_SYMBOL));
  ASSERT_NE(entry, nullptr);
  const auto* d = entry();
  EXPECT_STREQ(d->name, "obj_writer");
  EXPECT_EQ(d->kind, SHELLFLOW_KIND_WRITER);
  ShellflowCreateError error{};
  void* writer = d->create(R"({"folder": "m", "every": 2})",
                           sdk::context_to_json(sdk::Context{}).dump().c_str(), &error);
  ASSERT_NE(writer, nullptr) << error.message;
  d->destroy(writer);
  dlclose(library);
}

}  // namespace
}  // namespace shellflow::mesh_output::testing
