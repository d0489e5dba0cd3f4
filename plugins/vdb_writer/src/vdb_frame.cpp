#include "shellflow/vdb_writer/vdb_frame.hpp"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Prune.h>
#include <mutex>
#include <system_error>
#include <vector>

#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::vdb_writer {

namespace {

void initialize_openvdb_once() {
  static std::once_flag flag;
  std::call_once(flag, [] { openvdb::initialize(); });
}

const char* location_name(sdk::FieldView::Location location) {
  return location == sdk::FieldView::Location::Node ? "node" : "cell";
}

/// Voxel (i,j,k) centre = origin + dx (i,j,k): see the mapping in vdb_frame.hpp.
openvdb::math::Transform::Ptr sample_transform(const sdk::FieldView& field) {
  auto transform = openvdb::math::Transform::createLinearTransform(field.dx);
  transform->postTranslate(openvdb::Vec3d(field.origin.x(), field.origin.y(), field.origin.z()));
  return transform;
}

/// The index box of a field's samples, (0,0,0) .. dims - 1 (inclusive, OpenVDB style).
openvdb::CoordBBox sample_box(const sdk::FieldView& field) {
  return {openvdb::Coord(0, 0, 0),
          openvdb::Coord(field.dims[0] - 1, field.dims[1] - 1, field.dims[2] - 1)};
}

size_t sample_count(const sdk::FieldView& field) {
  return static_cast<size_t>(field.dims[0]) * static_cast<size_t>(field.dims[1]) *
         static_cast<size_t>(field.dims[2]);
}

void check_field(const sdk::FieldView& field) {
  if (field.components != 1 && field.components != 3)
    throw Error("vdb_writer: field \"" + field.name + "\" has " + std::to_string(field.components) +
                " components (1 or 3 expected)");
  for (int c = 0; c < field.components; ++c)
    if (field.data[c] == nullptr)
      throw Error("vdb_writer: field \"" + field.name + "\" has no data for component " +
                  std::to_string(c));
  if (!(field.dx > 0.0))
    throw Error("vdb_writer: field \"" + field.name + "\" has a non-positive spacing dx");
}

openvdb::GridBase::Ptr scalar_grid(const sdk::FieldView& field, const VdbOptions& options) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  // FieldView's flat layout i + nx (j + ny k) is OpenVDB's LayoutXYZ (x fastest). The
  // dense view only reads the data (copyFromDense), hence the const_cast.
  const openvdb::tools::Dense<double, openvdb::tools::LayoutXYZ> dense(
      sample_box(field), const_cast<double*>(field.data[0]));
  openvdb::tools::copyFromDense(dense, *grid, static_cast<float>(options.background_tolerance));
  grid->setGridClass(field.name == "density" ? openvdb::GRID_FOG_VOLUME : openvdb::GRID_UNKNOWN);
  return grid;
}

openvdb::GridBase::Ptr vector_grid(const sdk::FieldView& field, const VdbOptions& options) {
  auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  // Structure of arrays → interleaved vectors, as the dense view wants them.
  const size_t n = sample_count(field);
  std::vector<openvdb::Vec3d> interleaved(n);
  for (size_t s = 0; s < n; ++s)
    interleaved[s] = openvdb::Vec3d(field.data[0][s], field.data[1][s], field.data[2][s]);
  const openvdb::tools::Dense<openvdb::Vec3d, openvdb::tools::LayoutXYZ> dense(sample_box(field),
                                                                               interleaved.data());
  openvdb::tools::copyFromDense(dense, *grid,
                                openvdb::Vec3s(static_cast<float>(options.background_tolerance)));
  grid->setGridClass(openvdb::GRID_UNKNOWN);
  grid->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);  // a velocity (OpenVDB Types.h)
  return grid;
}

}  // namespace

std::string vdb_grid_name(const sdk::FieldView& field, const VdbOptions& options) {
  if (field.components == 3 && field.name == "velocity") return options.velocity_name;
  return field.name;
}

void write_vdb_frame(const std::filesystem::path& file, std::span<const sdk::FieldView> fields,
                     const VdbOptions& options, const VdbFrameInfo& info) {
  initialize_openvdb_once();
  openvdb::GridPtrVec grids;
  for (const auto& field : fields) {
    if (field.dims[0] <= 0 || field.dims[1] <= 0 || field.dims[2] <= 0) continue;
    check_field(field);
    openvdb::GridBase::Ptr grid =
        field.components == 1 ? scalar_grid(field, options) : vector_grid(field, options);
    grid->setName(vdb_grid_name(field, options));
    grid->setTransform(sample_transform(field));
    grid->setSaveFloatAsHalf(options.half_float);
    grid->insertMeta("shellflow_sample_location",
                     openvdb::StringMetadata(location_name(field.location)));
    grids.push_back(grid);
  }
  for (auto& grid : grids) {
    // Inactive all-background leaves and nodes collapse to tiles (smaller files).
    if (auto g = openvdb::gridPtrCast<openvdb::FloatGrid>(grid))
      openvdb::tools::pruneInactive(g->tree());
    if (auto g = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grid))
      openvdb::tools::pruneInactive(g->tree());
  }

  openvdb::MetaMap metadata;
  metadata.insertMeta("creator", openvdb::StringMetadata("shellflow vdb_writer"));
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
