#include "shellflow/liquid_writer/particle_files.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/points/PointConversion.h>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "shellflow/ply_writer/ply_writer.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/vdb_writer/vdb_file.hpp"

namespace shellflow::liquid_writer {

namespace {

std::string one_line(std::string text) {  // a line break would end a header line
  std::replace_if(
      text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return text;
}

openvdb::points::PointDataGrid::Ptr point_grid(const sdk::ParticleView& set, double voxel_size) {
  using namespace openvdb;
  const size_t n = static_cast<size_t>(set.count);
  std::vector<Vec3d> positions(n);
  std::vector<Vec3s> velocities(n);
  std::vector<float> radii(n);
  for (size_t i = 0; i < n; ++i) {
    positions[i] = Vec3d(set.position[0][i], set.position[1][i], set.position[2][i]);
    velocities[i] = set.velocity[0] ? Vec3s(static_cast<float>(set.velocity[0][i]),
                                            static_cast<float>(set.velocity[1][i]),
                                            static_cast<float>(set.velocity[2][i]))
                                    : Vec3s(0.0f);
    radii[i] = set.radius ? static_cast<float>(set.radius[i]) : 0.0f;
  }
  const auto transform = math::Transform::createLinearTransform(voxel_size);
  const points::PointAttributeVector<Vec3d> position_wrapper(positions);
  const auto index =
      tools::createPointIndexGrid<tools::PointIndexGrid>(position_wrapper, *transform);
  // NullCodec: positions stored as full floats (voxel-relative), not quantised.
  auto grid = points::createPointDataGrid<points::NullCodec, points::PointDataGrid>(
      *index, position_wrapper, *transform);
  auto& tree = grid->tree();
  points::appendAttribute<Vec3s>(tree, "v");
  points::populateAttribute(tree, index->tree(), "v",
                            points::PointAttributeVector<Vec3s>(velocities));
  points::appendAttribute<float>(tree, "pscale");
  points::populateAttribute(tree, index->tree(), "pscale",
                            points::PointAttributeVector<float>(radii));
  grid->setName(set.name);
  return grid;
}

}  // namespace

void write_particle_ply(std::ostream& out, const sdk::ParticleView& particles, int frame,
                        double time) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment shellflow liquid_writer: " +
      one_line(particles.name) + ", frame " + std::to_string(frame) +
      ", t = " + std::to_string(time) + " s\nelement vertex " + std::to_string(particles.count) +
      "\nproperty float x\nproperty float y\nproperty float z\n"
      "property float vx\nproperty float vy\nproperty float vz\n"
      "property float radius\nend_header\n";
  std::vector<char> bytes(header.begin(), header.end());
  bytes.reserve(bytes.size() + static_cast<size_t>(particles.count) * 28);
  for (std::int64_t i = 0; i < particles.count; ++i) {
    for (int a = 0; a < 3; ++a) ply_writer::put_float(bytes, particles.position[a][i]);
    for (int a = 0; a < 3; ++a)
      ply_writer::put_float(bytes, particles.velocity[a] ? particles.velocity[a][i] : 0.0);
    ply_writer::put_float(bytes, particles.radius ? particles.radius[i] : 0.0);
  }
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void write_particle_vdb(const std::filesystem::path& file, std::span<const sdk::ParticleView> sets,
                        double voxel_size, const ParticleVdbInfo& info) {
  if (!(voxel_size > 0.0))
    throw Error("liquid_writer: the particles' voxel size must be > 0 (a runtime bug)");
  vdb_writer::initialize_openvdb_once();
  openvdb::GridPtrVec grids;
  for (const auto& set : sets) grids.push_back(point_grid(set, voxel_size));
  vdb_writer::write_vdb_grids(file, grids, "shellflow liquid_writer", info);
}

}  // namespace shellflow::liquid_writer
