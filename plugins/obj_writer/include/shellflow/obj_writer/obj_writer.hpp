#pragma once
// The "obj_writer" writer: one Wavefront OBJ file per shell per frame (positions and
// triangles; OBJ has no place for velocities, see ply_writer). Coordinates are written
// in the shortest decimal form that reads back as the same double.

#include <nlohmann/json.hpp>
#include <ostream>

#include "shellflow/mesh_output/mesh_sequence_writer.hpp"
#include "shellflow/sdk/context.hpp"

namespace shellflow::obj_writer {

/// `v x y z` per node, `f a b c` (1-based) per triangle, after a comment naming the shell,
/// frame and time.
void write_obj(std::ostream& out, const sdk::ShellSurface& shell, int frame, double time);

class ObjWriter final : public mesh_output::MeshSequenceWriter {
 public:
  static sdk::Schema schema();
  ObjWriter(const nlohmann::json& params, const sdk::Context& context);

 protected:
  void write_shell(std::ostream& out, const sdk::ShellSurface& shell,
                   const sdk::FrameView& frame) const override;
};

}  // namespace shellflow::obj_writer
