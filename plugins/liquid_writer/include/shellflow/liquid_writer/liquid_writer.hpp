#pragma once
// The "liquid_writer" writer: the water of a water scene as files an effects artist takes
// into Houdini or Blender, per written frame, under `<out_dir>/<folder>/`:
//   <scene>_surface_<frame>.obj   the water's surface (liquid_mesher.hpp): positions and
//                                 triangles, closed, never across a shell
//   <scene>_surface_<frame>.ply   the same, binary, with per-vertex velocity vx vy vz
//   <scene>_<set>_<frame>.ply     each chosen particle set as a point cloud
//   <scene>_particles_<frame>.vdb the chosen particle sets as OpenVDB point grids
// (particle_files.hpp). The sets are the fluid's particles(): "spray" (water the particle
// level set removed, flying ballistically), "escaped_water" (water marker particles
// outside the water by more than their radius), "water_particles", "air_particles" (all
// marker particles). A fluid without a level set "phi" (smoke) or a scene without a fluid
// writes nothing; a fluid without particles writes empty particle files.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/liquid_writer/liquid_mesher.hpp"
#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::liquid_writer {

/// `<scene>_<what>_<frame, 4 digits at least>.<extension>`.
std::string liquid_file_name(const std::string& scene_name, const std::string& what, int frame,
                             const std::string& extension);

class LiquidWriter final : public sdk::Writer {
 public:
  static sdk::Schema schema();
  /// `params` validated against schema(). @throw ConfigError naming the parameter.
  LiquidWriter(const nlohmann::json& params, const sdk::Context& context);

  /// Creates `<out_dir>/<folder>`. @throw IoError naming the folder.
  void begin(const sdk::RunInfo& info) override;
  /// @throw IoError naming the file.
  void write_frame(const sdk::FrameView& frame) override;

  const std::filesystem::path& folder() const { return m_folder; }
  const LiquidMeshOptions& mesh_options() const { return m_mesh_options; }

 private:
  void write_mesh(const sdk::FrameView& frame, const sdk::FieldView& phi,
                  const sdk::FieldView* velocity) const;
  void write_particles(const sdk::FrameView& frame, double voxel_size) const;

  std::string m_folder_name;
  int m_every = 1;
  bool m_obj = true, m_ply = true;
  LiquidMeshOptions m_mesh_options;
  std::vector<std::string> m_particle_sets;
  bool m_particle_ply = true, m_particle_vdb = true;
  std::string m_scene_name;
  std::filesystem::path m_folder;
};

}  // namespace shellflow::liquid_writer
