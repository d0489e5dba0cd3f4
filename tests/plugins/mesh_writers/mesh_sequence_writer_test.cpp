// What every per-frame mesh writer shares: file names, "every", atomic files, errors.
#include "shellflow/mesh_output/mesh_sequence_writer.hpp"

#include <fstream>
#include <vector>

#include "mesh_writer_fixture.hpp"
#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/obj_writer/obj_writer.hpp"
#include "shellflow/ply_writer/ply_writer.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::mesh_output::testing {
namespace {

using sdk::write_file_atomically;

TEST(FrameFileName, ReplacesSlashesAndPadsTheFrame) {
  EXPECT_EQ(frame_file_name("solids/cup", 3, "obj"), "solids_cup_0003.obj");
  EXPECT_EQ(frame_file_name("a/b/c", 12345, "ply"), "a_b_c_12345.ply");
  EXPECT_EQ(frame_file_name("curtain", 0, "obj"), "curtain_0000.obj");
}

TEST_F(MeshWriterTest, WritesEveryNthFrameForEveryShellAndNothingElse) {
  const std::vector<sdk::ShellSurface> shells = {known_shell("cloth/sheet"), known_shell("cup")};
  obj_writer::ObjWriter obj({{"folder", "objs"}, {"every", 3}}, {});
  ply_writer::PlyWriter ply({{"every", 2}}, {});
  obj.begin(run_info());
  ply.begin(run_info());
  for (int frame = 0; frame <= 7; ++frame) {
    const sdk::FrameView view{frame, frame / 24.0, shells, nullptr};
    obj.write_frame(view);
    ply.write_frame(view);
  }
  EXPECT_EQ(files_in(m_out / "objs"),
            (std::set<std::string>{"cloth_sheet_0000.obj", "cup_0000.obj", "cloth_sheet_0003.obj",
                                   "cup_0003.obj", "cloth_sheet_0006.obj", "cup_0006.obj"}));
  // Default folder "meshes"; no temporary file is left behind.
  EXPECT_EQ(files_in(m_out / "meshes"),
            (std::set<std::string>{"cloth_sheet_0000.ply", "cup_0000.ply", "cloth_sheet_0002.ply",
                                   "cup_0002.ply", "cloth_sheet_0004.ply", "cup_0004.ply",
                                   "cloth_sheet_0006.ply", "cup_0006.ply"}));
}

TEST_F(MeshWriterTest, FolderThatCannotBeCreatedIsAnIoErrorNamingIt) {
  std::ofstream(m_out / "meshes") << "a file where the folder should go";
  obj_writer::ObjWriter writer(nlohmann::json::object(), {});
  try {
    writer.begin(run_info());
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find((m_out / "meshes").string()), std::string::npos)
        << e.what();
  }
}

TEST_F(MeshWriterTest, FailedWriteLeavesNeitherFileNorTemporary) {
  const auto file = m_out / "frame_0001.obj";
  // A stream that goes bad mid-way stands for a full disk.
  try {
    write_file_atomically(file, [](std::ostream& out) {
      out << "v 0 0 0\n";
      out.setstate(std::ios::badbit);
    });
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_TRUE(files_in(m_out).empty());
  // An exception inside the body propagates, with the same clean-up.
  EXPECT_THROW(write_file_atomically(file, [](std::ostream&) { throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_TRUE(files_in(m_out).empty());
  // A missing folder: the temporary cannot be created.
  EXPECT_THROW(write_file_atomically(m_out / "no" / "such.obj", [](std::ostream&) {}), IoError);
}

TEST_F(MeshWriterTest, RewritingAFrameReplacesItWhole) {
  const auto file = m_out / "f.obj";
  write_file_atomically(file, [](std::ostream& out) { out << std::string(1000, 'x'); });
  write_file_atomically(file, [](std::ostream& out) { out << "short"; });
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "short");
}

TEST(MeshSequenceSchema, DocumentsFolderAndEvery) {
  const auto schema = obj_writer::ObjWriter::schema().json();
  EXPECT_EQ(schema.at("fields").at("folder").at("default"), "meshes");
  EXPECT_EQ(schema.at("fields").at("every").at("default"), 1);
  EXPECT_EQ(schema.at("fields").at("every").at("min"), 1);
  EXPECT_THROW(ply_writer::PlyWriter({{"every", 0}}, {}), ConfigError);
}

}  // namespace
}  // namespace shellflow::mesh_output::testing
