#include "shellflow/liquid_writer/liquid_writer.hpp"

#include <algorithm>
#include <cstdio>

#include "shellflow/liquid_writer/particle_files.hpp"
#include "shellflow/obj_writer/obj_writer.hpp"
#include "shellflow/ply_writer/ply_writer.hpp"
#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::liquid_writer {

namespace {

const std::vector<std::string> kParticleSets{"spray", "escaped_water", "water_particles",
                                             "air_particles"};
const std::vector<std::string> kDefaultParticleSets{"spray", "escaped_water"};

/// The strings of the array `params[key]`, each one of `allowed`. @throw ConfigError.
std::vector<std::string> string_list(const nlohmann::json& params, const std::string& key,
                                     const std::vector<std::string>& defaults,
                                     const std::vector<std::string>& allowed) {
  if (!params.contains(key)) return defaults;
  const auto& list = params.at(key);
  std::string choices;
  for (const auto& a : allowed) choices += (choices.empty() ? "\"" : ", \"") + a + "\"";
  if (!list.is_array())
    throw ConfigError("/" + key, "must be an array of strings among " + choices);
  std::vector<std::string> out;
  for (size_t i = 0; i < list.size(); ++i) {
    const auto& item = list[i];
    if (!item.is_string() ||
        std::find(allowed.begin(), allowed.end(), item.get<std::string>()) == allowed.end())
      throw ConfigError("/" + key + "/" + std::to_string(i), "must be one of " + choices);
    out.push_back(item.get<std::string>());
  }
  return out;
}

bool has(const std::vector<std::string>& list, const std::string& value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

}  // namespace

std::string liquid_file_name(const std::string& scene_name, const std::string& what, int frame,
                             const std::string& extension) {
  char number[16];
  std::snprintf(number, sizeof number, "%04d", frame);
  return scene_name + "_" + what + "_" + number + "." + extension;
}

sdk::Schema LiquidWriter::schema() {
  using sdk::Schema;
  using Json = Schema::Json;
  return Schema::object(
             "the water for Houdini and Blender, per frame in <folder>: its surface meshed by "
             "OpenVDB (<scene>_surface_<frame>.obj, and .ply with per-vertex velocity vx vy "
             "vz; closed, never across a shell: the cells a shell touches are left out), and "
             "particle sets as PLY point clouds (<scene>_<set>_<frame>.ply: x y z vx vy vz "
             "radius) and OpenVDB point grids (<scene>_particles_<frame>.vdb, one grid per "
             "set, attributes P, v, pscale)")
      .field("folder",
             Schema::string("liquid").subfolder().doc("sub-folder of the run's output folder"))
      .field("every", Schema::integer(1).min(1).doc("write every n-th frame (frame 0, n, 2n, ...)"))
      .field("mesh", Schema::array(Schema::string().one_of({"obj", "ply"}))
                         .default_value(Json::array({"obj", "ply"}))
                         .doc("formats of the surface mesh; [] writes none"))
      .field("adaptivity",
             Schema::number(0.0).min(0.0).max(1.0).doc(
                 "OpenVDB's mesh adaptivity: 0 one vertex per cell the surface crosses, up to "
                 "1 flat regions merged into ever larger polygons (never within two cells of a "
                 "shell); small values already merge much (a sphere 19 cells in radius: 6920 "
                 "vertices at 0, 587 at 0.05, 158 at 0.2)"))
      .field("smoothing",
             Schema::integer(0).min(0).max(20).unit("passes").doc(
                 "Gaussian filter passes over the level set before meshing (OpenVDB "
                 "LevelSetFilter, 1-voxel radius); each rounds features of about a cell"))
      .field("particles",
             Schema::array(Schema::string().one_of(
                               {"spray", "escaped_water", "water_particles", "air_particles"}))
                 .default_value(Json::array({"spray", "escaped_water"}))
                 .doc("particle sets to write: \"spray\" (water the particle level set removed, "
                      "flying under gravity until it lands), \"escaped_water\" (water marker "
                      "particles outside the water by more than their radius: drops the level "
                      "set does not hold), \"water_particles\" and \"air_particles\" (all "
                      "marker particles of each sign); needs /fluid/water/particles/per_cell > "
                      "0, else the files are empty"))
      .field("particle_formats", Schema::array(Schema::string().one_of({"ply", "vdb"}))
                                     .default_value(Json::array({"ply", "vdb"}))
                                     .doc("formats of the particle files; [] writes none"));
}

LiquidWriter::LiquidWriter(const nlohmann::json& params, const sdk::Context& /*context*/)
    : m_folder_name(params.value("folder", std::string("liquid"))),
      m_every(params.value("every", 1)) {
  if (m_every < 1) throw ConfigError("/every", "must be at least 1");
  sdk::check_subfolder(m_folder_name, "/folder");
  const auto mesh = string_list(params, "mesh", {"obj", "ply"}, {"obj", "ply"});
  m_obj = has(mesh, "obj");
  m_ply = has(mesh, "ply");
  m_mesh_options.adaptivity = params.value("adaptivity", 0.0);
  if (!(m_mesh_options.adaptivity >= 0.0 && m_mesh_options.adaptivity <= 1.0))
    throw ConfigError("/adaptivity", "must be a number in [0, 1]");
  m_mesh_options.smoothing_iterations = params.value("smoothing", 0);
  if (m_mesh_options.smoothing_iterations < 0 || m_mesh_options.smoothing_iterations > 20)
    throw ConfigError("/smoothing", "must be an integer in [0, 20]");
  m_particle_sets = string_list(params, "particles", kDefaultParticleSets, kParticleSets);
  const auto formats = string_list(params, "particle_formats", {"ply", "vdb"}, {"ply", "vdb"});
  m_particle_ply = has(formats, "ply");
  m_particle_vdb = has(formats, "vdb");
}

void LiquidWriter::begin(const sdk::RunInfo& info) {
  m_scene_name = info.scene_name;
  m_folder = sdk::make_output_subfolder(info, m_folder_name);
}

void LiquidWriter::write_frame(const sdk::FrameView& frame) {
  if (m_folder.empty())
    throw Error("liquid_writer: write_frame() called before begin() (a runtime bug)");
  if (frame.frame % m_every != 0 || frame.fluid == nullptr) return;
  const std::vector<sdk::FieldView> fields = frame.fluid->fields();
  const sdk::FieldView* phi = nullptr;
  const sdk::FieldView* velocity = nullptr;
  for (const auto& f : fields) {
    if (f.name == "phi" && f.components == 1) phi = &f;  // on the nodes or the cell centres
    if (f.name == "velocity" && f.components == 3 && f.location == sdk::FieldView::Location::Node)
      velocity = &f;
  }
  if (phi == nullptr) return;  // no water
  // A node φ takes the velocity on its own nodes; a cell φ samples it at the vertices.
  if (velocity != nullptr && phi->location == sdk::FieldView::Location::Node &&
      velocity->dims != phi->dims)
    velocity = nullptr;
  if (m_obj || m_ply) write_mesh(frame, *phi, velocity);
  if (!m_particle_sets.empty() && (m_particle_ply || m_particle_vdb))
    write_particles(frame, phi->dx);
}

void LiquidWriter::write_mesh(const sdk::FrameView& frame, const sdk::FieldView& phi,
                              const sdk::FieldView* velocity) const {
  LiquidMesh mesh = mesh_liquid(phi, velocity, frame.shells, m_mesh_options);
  // The mesh writers' formats, reused: a mesh is written as a shell surface.
  sdk::ShellSurface surface;
  surface.name = "water surface";
  surface.positions = std::move(mesh.positions);
  surface.velocities = std::move(mesh.velocities);
  surface.triangles = std::make_shared<const sdk::Triangles>(std::move(mesh.triangles));
  if (m_obj)
    sdk::write_file_atomically(
        m_folder / liquid_file_name(m_scene_name, "surface", frame.frame, "obj"),
        [&](std::ostream& out) { obj_writer::write_obj(out, surface, frame.frame, frame.time); });
  if (m_ply)
    sdk::write_file_atomically(
        m_folder / liquid_file_name(m_scene_name, "surface", frame.frame, "ply"),
        [&](std::ostream& out) { ply_writer::write_ply(out, surface, frame.frame, frame.time); });
}

void LiquidWriter::write_particles(const sdk::FrameView& frame, double voxel_size) const {
  const std::vector<sdk::ParticleView> available = frame.fluid->particles();
  std::vector<sdk::ParticleView> chosen;
  for (const std::string& name : m_particle_sets) {
    const auto found = std::find_if(available.begin(), available.end(),
                                    [&](const sdk::ParticleView& v) { return v.name == name; });
    sdk::ParticleView view;
    if (found != available.end()) {
      view = *found;
    } else {
      view.name = name;  // this fluid has none: an empty set, so every frame has its files
    }
    chosen.push_back(view);
  }
  if (m_particle_ply)
    for (const auto& set : chosen)
      sdk::write_file_atomically(
          m_folder / liquid_file_name(m_scene_name, set.name, frame.frame, "ply"),
          [&](std::ostream& out) { write_particle_ply(out, set, frame.frame, frame.time); });
  if (m_particle_vdb)
    write_particle_vdb(m_folder / liquid_file_name(m_scene_name, "particles", frame.frame, "vdb"),
                       chosen, voxel_size, {m_scene_name, frame.frame, frame.time});
}

}  // namespace shellflow::liquid_writer
