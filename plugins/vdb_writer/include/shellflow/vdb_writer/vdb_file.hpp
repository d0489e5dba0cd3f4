#pragma once
// OpenVDB files as shellflow writes them, for the writers that build their own grids
// (vdb_writer's fields, liquid_writer's meshes and point grids). Includes OpenVDB: a
// target using it links OpenVDB itself.

#include <openvdb/openvdb.h>

#include <filesystem>
#include <string>

#include "shellflow/vdb_writer/vdb_frame.hpp"

namespace shellflow::vdb_writer {

/// openvdb::initialize(), once per process.
void initialize_openvdb_once();

/// Writes `grids` to `file` with the metadata "creator" (`creator`), "shellflow_scene",
/// "shellflow_frame" and "shellflow_time", through a temporary file in the same folder
/// renamed into place. @throw IoError naming the file when writing or renaming fails.
void write_vdb_grids(const std::filesystem::path& file, const openvdb::GridPtrVec& grids,
                     const std::string& creator, const VdbFrameInfo& info);

}  // namespace shellflow::vdb_writer
