#pragma once
// One frame of grid fields as an OpenVDB file (the format Blender and Houdini read).
// OpenVDB itself is not included here: it is heavy and only vdb_frame.cpp needs it.
//
// Mapping (OpenVDB convention: the value of voxel (i,j,k) sits at the voxel's centre,
// world = transform.indexToWorld(i,j,k)):
//   - transform: uniform scale dx, then translation by FieldView::origin, so voxel
//     (i,j,k) lands exactly on sample (i,j,k) = origin + dx (i,j,k). Cell-centred fields
//     carry origin = domain corner + dx/2, node fields origin = domain corner; both come
//     out at their true sample positions. The location is also stored as grid metadata
//     "shellflow_sample_location" ("cell" / "node").
//   - scalars → FloatGrid, vectors (3 components) → Vec3SGrid; values are rounded from
//     double to float (float is chosen for file size; renderers read float).
//   - samples whose value (each component, for vectors) is within `background_tolerance`
//     of 0 become the inactive background 0: the grid stores only the smoke.
//   - "density" has grid class FOG_VOLUME; vectors are VEC_CONTRAVARIANT_RELATIVE (a
//     velocity); the vector field "velocity" is named `velocity_name`.
//   - the water's level set, the scalar field "phi" (φ ≤ 0 water, a signed distance [m]
//     near the surface), becomes the FloatGrid "surface" (the name Houdini gives an SDF)
//     of class LEVEL_SET, in OpenVDB's narrow-band form: background b = min(
//     level_set_half_width dx, max |φ|) > 0, voxels with |φ| < b active with φ, the rest
//     inactive at −b (water) or +b (air, and everything outside the field's box). b never
//     exceeds the fluid's own clamp, so a narrower fluid band does not activate its
//     plateau. `background_tolerance` does not apply to it.

#include <filesystem>
#include <span>
#include <string>

#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::vdb_writer {

/// The fluid field written as a level set, and its grid name in the file.
inline constexpr const char* kLevelSetField = "phi";
inline constexpr const char* kLevelSetGridName = "surface";

struct VdbOptions {
  double background_tolerance = 0.0;       ///< |value| <= this → inactive background
  std::string velocity_name = "velocity";  ///< "velocity" (Blender) or "vel" (Houdini)
  bool half_float = false;                 ///< store floats as 16-bit halves on disk
  double level_set_half_width = 3.0;       ///< "surface" band half-width [voxels]
};

/// Per-file metadata.
struct VdbFrameInfo {
  std::string scene_name;
  int frame = 0;
  double time = 0.0;  ///< [s]
};

/// The grid name a field gets in the file.
std::string vdb_grid_name(const sdk::FieldView& field, const VdbOptions& options);

/// Writes `fields` (those with 1 or 3 components and non-empty dims) to `file`, through a
/// temporary file in the same folder renamed into place. Calls openvdb::initialize()
/// once per process. @throw IoError naming the file when writing or renaming fails;
/// Error when a field is malformed (components not 1 or 3, null data).
void write_vdb_frame(const std::filesystem::path& file, std::span<const sdk::FieldView> fields,
                     const VdbOptions& options, const VdbFrameInfo& info);

}  // namespace shellflow::vdb_writer
