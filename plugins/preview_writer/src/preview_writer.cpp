#include "shellflow/preview_writer/preview_writer.hpp"

#include <cstdio>
#include <stdexcept>
#include <system_error>

#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::preview_writer {

std::string preview_file_name(const std::string& scene_name, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return scene_name + "_" + number + ".png";
}

namespace {

sdk::Schema colour(double r, double g, double b, const std::string& doc) {
  return sdk::Schema::vec3(r, g, b).doc(doc + " (linear RGB, components in [0, 1])");
}

Eigen::Vector3d read_colour(const nlohmann::json& params, const std::string& key) {
  const Eigen::Vector3d c = sdk::json_vec3(params, key);
  if ((c.array() < 0.0).any() || (c.array() > 1.0).any())
    throw ConfigError("/" + key, "colour components must lie in [0, 1]");
  return c;
}

}  // namespace

sdk::Schema PreviewWriter::schema() {
  using sdk::Schema;
  const PreviewSettings d;
  return Schema::object(
             "a PNG preview per frame, <folder>/<scene>_<frame>.png: smoke density ray-marched "
             "with Beer-Lambert absorption, the water surface (level set phi = 0) ray-cast and "
             "shaded, shells as shaded opaque triangles that hide the smoke and water behind "
             "them")
      .field("folder",
             Schema::string("previews").subfolder().doc("sub-folder of the run's output folder"))
      .field("every", Schema::integer(1).min(1).doc("write every n-th frame (frame 0, n, 2n, ...)"))
      .field("camera",
             Schema::object("pinhole camera")
                 .field("position", Schema::vec3(d.camera_position.x(), d.camera_position.y(),
                                                 d.camera_position.z())
                                        .unit("m")
                                        .doc("eye point"))
                 .field("look_at", Schema::vec3(d.look_at.x(), d.look_at.y(), d.look_at.z())
                                       .unit("m")
                                       .doc("point at the image centre"))
                 .field("up", Schema::vec3(d.up.x(), d.up.y(), d.up.z())
                                  .doc("direction that is up in the image"))
                 .field("fov_deg", Schema::number(d.vertical_fov_deg)
                                       .min(0.0, false)
                                       .max(180.0, false)
                                       .unit("deg")
                                       .doc("vertical field of view"))
                 .field("width",
                        Schema::integer(d.width).min(1).max(16384).unit("px").doc("image width"))
                 .field("height",
                        Schema::integer(d.height).min(1).max(16384).unit("px").doc("image height")))
      .field("absorption", Schema::number(d.absorption)
                               .min(0.0)
                               .unit("1/m per unit density")
                               .doc("sigma in the transmittance exp(-sigma * integral of density)"))
      .field("step_voxels", Schema::number(d.step_voxels)
                                .min(0.01)
                                .max(4.0)
                                .doc("ray-march step in units of the density grid spacing"))
      .field("smoke_color", colour(d.smoke_color.x(), d.smoke_color.y(), d.smoke_color.z(),
                                   "colour of opaque smoke"))
      .field("background_color", colour(d.background_color.x(), d.background_color.y(),
                                        d.background_color.z(), "colour where a ray meets nothing"))
      .field("shell_color", colour(d.shell_color.x(), d.shell_color.y(), d.shell_color.z(),
                                   "colour of a shell facing the camera"))
      .field("ambient", Schema::number(d.ambient).min(0.0).max(1.0).doc(
                            "shade of a shell seen edge-on, as a fraction of its colour"))
      .field("density_field",
             Schema::string(d.density_field).doc("name of the fluid field drawn as smoke"))
      .field("water_color", colour(d.water_color.x(), d.water_color.y(), d.water_color.z(),
                                   "colour of the water surface facing the camera"))
      .field("water_rim_color",
             colour(d.water_rim_color.x(), d.water_rim_color.y(), d.water_rim_color.z(),
                    "colour the water surface turns to where it is seen edge-on (Fresnel)"))
      .field("water_field",
             Schema::string(d.water_field)
                 .doc("name of the fluid's level set field (phi <= 0 water) drawn as a surface; "
                      "marched with step min(step_voxels, 0.5) grid spacings"))
      .field("walls",
             Schema::boolean(d.walls).doc(
                 "draw the fluid domain's closed sides behind everything in it, seen from "
                 "inside: the floor (the wall gravity points into) with a grid of 1, 2 or 5 x "
                 "10^k m squares, the other walls flat, the box's edges along walls as thin "
                 "lines; open and inflow sides are not drawn"))
      .field("floor_shadow",
             Schema::number(d.floor_shadow)
                 .min(0.0)
                 .max(1.0)
                 .doc("how much the shadow of the water and smoke under a light straight above "
                      "darkens the floor (the floor's colour times 1 - floor_shadow in full "
                      "shadow; 0: none): water in mid-air shows where it is above the floor"))
      .field("floor_color", colour(d.wall_colours.floor.x(), d.wall_colours.floor.y(),
                                   d.wall_colours.floor.z(), "colour of the floor"))
      .field("grid_color",
             colour(d.wall_colours.grid.x(), d.wall_colours.grid.y(), d.wall_colours.grid.z(),
                    "colour of the floor's grid lines and of the box's edges"))
      .field("wall_color",
             colour(d.wall_colours.wall.x(), d.wall_colours.wall.y(), d.wall_colours.wall.z(),
                    "colour of the walls other than the floor"));
}

PreviewSettings preview_settings_from_json(const nlohmann::json& params) {
  PreviewSettings s;
  const nlohmann::json camera = params.value("camera", nlohmann::json::object());
  if (camera.contains("position")) s.camera_position = sdk::json_vec3(camera, "position");
  if (camera.contains("look_at")) s.look_at = sdk::json_vec3(camera, "look_at");
  if (camera.contains("up")) s.up = sdk::json_vec3(camera, "up");
  s.vertical_fov_deg = camera.value("fov_deg", s.vertical_fov_deg);
  s.width = camera.value("width", s.width);
  s.height = camera.value("height", s.height);
  s.absorption = params.value("absorption", s.absorption);
  s.step_voxels = params.value("step_voxels", s.step_voxels);
  if (params.contains("smoke_color")) s.smoke_color = read_colour(params, "smoke_color");
  if (params.contains("background_color"))
    s.background_color = read_colour(params, "background_color");
  if (params.contains("shell_color")) s.shell_color = read_colour(params, "shell_color");
  if (params.contains("water_color")) s.water_color = read_colour(params, "water_color");
  if (params.contains("water_rim_color"))
    s.water_rim_color = read_colour(params, "water_rim_color");
  if (params.contains("floor_color")) s.wall_colours.floor = read_colour(params, "floor_color");
  if (params.contains("grid_color")) s.wall_colours.grid = read_colour(params, "grid_color");
  if (params.contains("wall_color")) s.wall_colours.wall = read_colour(params, "wall_color");
  s.walls = params.value("walls", s.walls);
  s.floor_shadow = params.value("floor_shadow", s.floor_shadow);
  s.ambient = params.value("ambient", s.ambient);
  s.density_field = params.value("density_field", s.density_field);
  s.water_field = params.value("water_field", s.water_field);
  if (!(s.absorption >= 0.0)) throw ConfigError("/absorption", "must be >= 0");
  if (!(s.step_voxels > 0.0)) throw ConfigError("/step_voxels", "must be > 0");
  try {
    const Camera check(s.camera_position, s.look_at, s.up, s.vertical_fov_deg, s.width, s.height);
  } catch (const std::invalid_argument& e) {
    throw ConfigError("/camera", std::string(e.what()) + "; move look_at or change up");
  }
  return s;
}

PreviewSettings preview_settings_from_json(const nlohmann::json& params,
                                           const sdk::Context& context) {
  PreviewSettings s = preview_settings_from_json(params);
  const Eigen::Vector3d& g = context.gravity;
  // Without gravity the floor is the wall below the camera (the one down in the image).
  s.down = g.allFinite() && g.norm() > 0.0 ? g : Eigen::Vector3d(-s.up);
  return s;
}

PreviewWriter::PreviewWriter(const nlohmann::json& params, const sdk::Context& context)
    : m_folder_name(params.value("folder", std::string("previews"))),
      m_every(params.value("every", 1)),
      m_renderer(preview_settings_from_json(params, context)) {
  if (m_every < 1) throw ConfigError("/every", "must be at least 1");
  sdk::check_subfolder(m_folder_name, "/folder");
}

void PreviewWriter::begin(const sdk::RunInfo& info) {
  m_scene_name = info.scene_name;
  m_folder = sdk::make_output_subfolder(info, m_folder_name);
}

void PreviewWriter::write_frame(const sdk::FrameView& frame) {
  if (m_folder.empty())
    throw Error("preview_writer: write_frame() called before begin() (a runtime bug)");
  if (frame.frame % m_every != 0) return;
  write_png(m_folder / preview_file_name(m_scene_name, frame.frame), m_renderer.render(frame));
}

}  // namespace shellflow::preview_writer
