#include "shellflow/vdb_writer/vdb_file.hpp"

#include <openvdb/io/File.h>

#include <mutex>

#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::vdb_writer {

void initialize_openvdb_once() {
  static std::once_flag flag;
  std::call_once(flag, [] { openvdb::initialize(); });
}

void write_vdb_grids(const std::filesystem::path& file, const openvdb::GridPtrVec& grids,
                     const std::string& creator, const VdbFrameInfo& info) {
  openvdb::MetaMap metadata;
  metadata.insertMeta("creator", openvdb::StringMetadata(creator));
  metadata.insertMeta("shellflow_scene", openvdb::StringMetadata(info.scene_name));
  metadata.insertMeta("shellflow_frame", openvdb::Int32Metadata(info.frame));
  metadata.insertMeta("shellflow_time", openvdb::DoubleMetadata(info.time));
  sdk::replace_file_atomically(file, [&](const std::filesystem::path& temporary) {
    try {
      openvdb::io::File out(temporary.string());
      out.write(grids, metadata);
      out.close();
    } catch (const openvdb::Exception& e) {
      throw IoError(file.string() + ": cannot write the OpenVDB file (" + e.what() + ")");
    }
  });
}

}  // namespace shellflow::vdb_writer
