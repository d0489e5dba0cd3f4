#pragma once
// Particle sets (sdk::ParticleView: spray, marker particles) as files per frame:
//  - binary little-endian PLY point clouds: `element vertex` with float x y z (position
//    [m]), vx vy vz (velocity [m/s]) and radius [m], no faces;
//  - one OpenVDB file holding a points::PointDataGrid per set, named after it, with
//    Houdini's attribute names: "P" (position, full 32-bit floats), "v" (velocity, Vec3s)
//    and "pscale" (radius, float). Houdini reads them as point clouds.
// OpenVDB is not included here.

#include <filesystem>
#include <ostream>
#include <span>
#include <string>

#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/vdb_writer/vdb_frame.hpp"

namespace shellflow::liquid_writer {

/// The PLY point cloud of `particles`, with a comment naming the set, frame and time.
void write_particle_ply(std::ostream& out, const sdk::ParticleView& particles, int frame,
                        double time);

/// The file's metadata: scene, frame, time (vdb_writer's, as its files carry).
using ParticleVdbInfo = vdb_writer::VdbFrameInfo;

/// Writes every set of `sets` as a PointDataGrid of voxel size `voxel_size` [m] (> 0) to
/// `file`, through a temporary file renamed into place. @throw IoError naming the file.
void write_particle_vdb(const std::filesystem::path& file, std::span<const sdk::ParticleView> sets,
                        double voxel_size, const ParticleVdbInfo& info);

}  // namespace shellflow::liquid_writer
