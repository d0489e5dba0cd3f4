#include "shellflow/vdb_writer/vdb_frame.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Prune.h>
#include <algorithm>
#include <cmath>
#include <memory>
#include <system_error>
#include <vector>

#include "shellflow/sdk/error.hpp"
#include "shellflow/vdb_writer/vdb_file.hpp"

namespace shellflow::vdb_writer {

namespace {

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
  // Inactive all-background leaves and nodes collapse to tiles (smaller files).
  openvdb::tools::pruneInactive(grid->tree());
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
  openvdb::tools::pruneInactive(grid->tree());
  return grid;
}

bool is_level_set(const sdk::FieldView& field) {
  return field.components == 1 && field.name == kLevelSetField;
}

/// min(half_width dx, max |φ|): the band half-width, never wider than the fluid's own
/// clamp (else the clamped plateau would be "inside the band" and all of it active). When
/// max |φ| is below half_width dx, samples with |φ| = max |φ| become inactive ±background,
/// which is their value: nothing is lost. All-zero φ falls back to half_width dx.
double level_set_background(const sdk::FieldView& field, double half_width_voxels) {
  const long n = static_cast<long>(sample_count(field));
  const double* phi = field.data[0];
  double largest = 0.0;
#pragma omp parallel for reduction(max : largest)
  for (long s = 0; s < n; ++s) largest = std::max(largest, std::abs(phi[s]));
  const double band = half_width_voxels * field.dx;
  return largest > 0.0 ? std::min(band, largest) : band;
}

/// A narrow-band level set in OpenVDB's convention (Museth 2013, "VDB: High-resolution
/// sparse volumes with dynamic topology"; what tools::meshToLevelSet produces): active
/// voxels hold φ where |φ| < background, inactive ones −background inside (φ < 0) and
/// +background outside. Built as a sparse fill, one 8³ leaf block per iteration (blocks in
/// parallel, then handed to the tree serially): a block with no band voxel becomes an
/// inactive −background tile when it lies wholly inside the water and the field's box,
/// and stays background (air) otherwise. The water's interior is never active, and stored
/// voxel by voxel only in blocks that the box's far faces cut.
openvdb::GridBase::Ptr level_set_grid(const sdk::FieldView& field, const VdbOptions& options) {
  using Leaf = openvdb::FloatTree::LeafNodeType;
  constexpr int kLeafDim = static_cast<int>(Leaf::DIM);
  const float background =
      static_cast<float>(level_set_background(field, options.level_set_half_width));
  auto grid = openvdb::FloatGrid::create(background);
  const std::array<int, 3> dims = field.dims;
  const std::array<int, 3> blocks{(dims[0] + kLeafDim - 1) / kLeafDim,
                                  (dims[1] + kLeafDim - 1) / kLeafDim,
                                  (dims[2] + kLeafDim - 1) / kLeafDim};
  const long block_count = static_cast<long>(blocks[0]) * blocks[1] * blocks[2];
  const double* phi = field.data[0];
  // Per block: its leaf when it holds band voxels, else whether it is an inside tile.
  std::vector<std::unique_ptr<Leaf>> leaves(static_cast<size_t>(block_count));
  std::vector<char> inside_tile(static_cast<size_t>(block_count), 0);

#pragma omp parallel for schedule(dynamic, 8)
  for (long b = 0; b < block_count; ++b) {
    const int bi = static_cast<int>(b % blocks[0]);
    const int bj = static_cast<int>((b / blocks[0]) % blocks[1]);
    const int bk = static_cast<int>(b / (static_cast<long>(blocks[0]) * blocks[1]));
    const openvdb::Coord origin(kLeafDim * bi, kLeafDim * bj, kLeafDim * bk);
    auto leaf = std::make_unique<Leaf>(origin, background, false);
    long band = 0, inside = 0;
    for (int k = origin.z(); k < std::min(origin.z() + kLeafDim, dims[2]); ++k)
      for (int j = origin.y(); j < std::min(origin.y() + kLeafDim, dims[1]); ++j)
        for (int i = origin.x(); i < std::min(origin.x() + kLeafDim, dims[0]); ++i) {
          const size_t s = static_cast<size_t>(i) +
                           static_cast<size_t>(dims[0]) *
                               (static_cast<size_t>(j) + static_cast<size_t>(dims[1]) * k);
          const float value = static_cast<float>(phi[s]);
          const openvdb::Index offset = Leaf::coordToOffset(openvdb::Coord(i, j, k));
          if (std::abs(value) < background) {
            leaf->setValueOn(offset, value);
            ++band;
          } else if (value < 0.0f) {
            leaf->setValueOff(offset, -background);
            ++inside;
          }
        }
    if (band > 0 || (inside > 0 && inside < static_cast<long>(Leaf::SIZE))) {
      // Band voxels, or inactive water beside air: against the box's far faces, where the
      // block's voxels beyond the box stay air.
      leaves[static_cast<size_t>(b)] = std::move(leaf);
    } else if (inside == static_cast<long>(Leaf::SIZE)) {
      inside_tile[static_cast<size_t>(b)] = 1;
    }
  }
  auto& tree = grid->tree();
  for (long b = 0; b < block_count; ++b) {
    if (auto& leaf = leaves[static_cast<size_t>(b)]) {
      tree.addLeaf(leaf.release());  // the tree takes ownership
    } else if (inside_tile[static_cast<size_t>(b)]) {
      const int bi = static_cast<int>(b % blocks[0]);
      const int bj = static_cast<int>((b / blocks[0]) % blocks[1]);
      const int bk = static_cast<int>(b / (static_cast<long>(blocks[0]) * blocks[1]));
      tree.addTile(/*level=*/1, openvdb::Coord(kLeafDim * bi, kLeafDim * bj, kLeafDim * bk),
                   -background, false);  // a leaf-sized tile
    }
  }
  // Merges uniform tiles upward. Not pruneLevelSet: it would give an all-inactive leaf
  // holding both signs (water at the box's far faces) the sign of its first voxel.
  openvdb::tools::prune(tree);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

}  // namespace

std::string vdb_grid_name(const sdk::FieldView& field, const VdbOptions& options) {
  if (field.components == 3 && field.name == "velocity") return options.velocity_name;
  if (is_level_set(field)) return kLevelSetGridName;
  return field.name;
}

void write_vdb_frame(const std::filesystem::path& file, std::span<const sdk::FieldView> fields,
                     const VdbOptions& options, const VdbFrameInfo& info) {
  initialize_openvdb_once();
  openvdb::GridPtrVec grids;
  for (const auto& field : fields) {
    if (field.dims[0] <= 0 || field.dims[1] <= 0 || field.dims[2] <= 0) continue;
    check_field(field);
    openvdb::GridBase::Ptr grid = is_level_set(field)     ? level_set_grid(field, options)
                                  : field.components == 1 ? scalar_grid(field, options)
                                                          : vector_grid(field, options);
    grid->setName(vdb_grid_name(field, options));
    grid->setTransform(sample_transform(field));
    grid->setSaveFloatAsHalf(options.half_float);
    grid->insertMeta("shellflow_sample_location",
                     openvdb::StringMetadata(location_name(field.location)));
    grids.push_back(grid);
  }

  write_vdb_grids(file, grids, "shellflow vdb_writer", info);
}

}  // namespace shellflow::vdb_writer
