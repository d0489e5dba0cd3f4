#include "shellflow/vdb_writer/vdb_writer.hpp"

#include <cstdio>
#include <system_error>
#include <vector>

#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::vdb_writer {

std::string vdb_file_name(const std::string& scene_name, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return scene_name + "_" + number + ".vdb";
}

sdk::Schema VdbWriter::schema() {
  using sdk::Schema;
  return Schema::object(
             "one OpenVDB file per frame, <folder>/<scene>_<frame>.vdb, with the fluid's grids "
             "(FloatGrid per scalar such as density and temperature, Vec3SGrid for velocity; "
             "the water's level set phi as the narrow-band level set FloatGrid \"surface\", "
             "class LEVEL_SET, background = its band half-width in metres, negative inside "
             "the water); readable by Blender and Houdini")
      .field("folder",
             Schema::string("volumes").subfolder().doc("sub-folder of the run's output folder"))
      .field("every", Schema::integer(1).min(1).doc("write every n-th frame (frame 0, n, 2n, ...)"))
      .field("background_tolerance",
             Schema::number(1e-4).min(0.0).doc(
                 "samples with |value| (every component, for vectors) at most this become the "
                 "inactive background 0, so files hold only where there is smoke"))
      .field("velocity_name",
             Schema::string("velocity")
                 .one_of({"velocity", "vel"})
                 .doc("grid name of the velocity: \"velocity\" (Blender) or \"vel\" (Houdini)"))
      .field("half_float",
             Schema::boolean(false).doc("store values as 16-bit floats on disk (half the size)"))
      .field("level_set_half_width",
             Schema::number(3.0).min(1.0).unit("voxels").doc(
                 "half-width of the \"surface\" grid's narrow band: voxels with |phi| below "
                 "it are active, the grid's background is this times dx (or the largest |phi| "
                 "when the fluid clamps phi closer to the surface)"));
}

VdbWriter::VdbWriter(const nlohmann::json& params, const sdk::Context& /*context*/)
    : m_folder_name(params.value("folder", std::string("volumes"))),
      m_every(params.value("every", 1)) {
  m_options.background_tolerance = params.value("background_tolerance", 1e-4);
  m_options.velocity_name = params.value("velocity_name", std::string("velocity"));
  m_options.half_float = params.value("half_float", false);
  m_options.level_set_half_width = params.value("level_set_half_width", 3.0);
  if (m_every < 1) throw ConfigError("/every", "must be at least 1");
  sdk::check_subfolder(m_folder_name, "/folder");
  if (!(m_options.background_tolerance >= 0.0))
    throw ConfigError("/background_tolerance", "must be a number >= 0");
  if (m_options.velocity_name != "velocity" && m_options.velocity_name != "vel")
    throw ConfigError("/velocity_name", "must be \"velocity\" or \"vel\"");
  if (!(m_options.level_set_half_width >= 1.0))
    throw ConfigError("/level_set_half_width", "must be a number >= 1 (voxels)");
}

void VdbWriter::begin(const sdk::RunInfo& info) {
  m_scene_name = info.scene_name;
  m_folder = sdk::make_output_subfolder(info, m_folder_name);
}

void VdbWriter::write_frame(const sdk::FrameView& frame) {
  if (m_folder.empty())
    throw Error("vdb_writer: write_frame() called before begin() (a runtime bug)");
  if (frame.frame % m_every != 0 || frame.fluid == nullptr) return;
  const std::vector<sdk::FieldView> fields = frame.fluid->fields();
  write_vdb_frame(m_folder / vdb_file_name(m_scene_name, frame.frame), fields, m_options,
                  {m_scene_name, frame.frame, frame.time});
}

}  // namespace shellflow::vdb_writer
