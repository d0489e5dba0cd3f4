#pragma once
// The "ply_writer" writer: one binary little-endian PLY file per shell per frame with
// per-node velocity:
//
//   element vertex N: property float x y z vx vy vz
//   element face M:   property list uchar int vertex_indices
//
// Single precision (float) is chosen for size and because viewers (Houdini, Blender,
// ParaView) read it; positions lose digits beyond ~1e-7 relative.

#include <nlohmann/json.hpp>
#include <ostream>
#include <vector>

#include "shellflow/mesh_output/mesh_sequence_writer.hpp"
#include "shellflow/sdk/context.hpp"

namespace shellflow::ply_writer {

/// Appends `value` as a 4-byte little-endian float, whatever the host's byte order (the
/// binary_little_endian PLY body; liquid_writer's point clouds use it too).
void put_float(std::vector<char>& bytes, double value);

/// Writes one shell; missing velocities (a matrix of another size) are written as zero.
void write_ply(std::ostream& out, const sdk::ShellSurface& shell, int frame, double time);

class PlyWriter final : public mesh_output::MeshSequenceWriter {
 public:
  static sdk::Schema schema();
  PlyWriter(const nlohmann::json& params, const sdk::Context& context);

 protected:
  void write_shell(std::ostream& out, const sdk::ShellSurface& shell,
                   const sdk::FrameView& frame) const override;
};

}  // namespace shellflow::ply_writer
