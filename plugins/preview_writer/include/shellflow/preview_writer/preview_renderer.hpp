#pragma once
// PreviewRenderer: one frame as an image, the way the paper's renderer shows smoke, water
// and shells (Guendelman et al. 2005, §7: smoke and water behind a shell stay hidden):
//   - each pixel's ray first finds the nearest shell triangle (ShellScene);
//   - the water surface, the level set φ = 0 (WaterSurface), is searched from the camera
//     up to that hit (or through the whole grid): water behind the shell stays hidden, and
//     water in front of it hides it;
//   - the smoke density is ray-marched front to back from the camera up to the nearer of
//     the two hits (or through the whole volume), Beer–Lambert absorption:
//     T = exp(−σ ∫ρ ds);
//   - pixel = smoke_colour (1 − T) + T · behind, where behind is the water's or the
//     shell's shade or the background. Shells: Lambert with a headlight, two-sided,
//     colour (a + (1 − a) |n·d|). Water: the same Lambert with water_colour, mixed
//     towards water_rim_colour by Schlick's Fresnel term F = F0 + (1 − F0)(1 − |n·d|)^5
//     (Schlick 1994; F0 = 0.02 for water, ((1.33 − 1)/(1.33 + 1))²): (1 − F) · lambert + F ·
//     rim, a brighter rim where the surface turns away from the camera.
// With one smoke colour, front-to-back compositing Σ T_i α_i c = c (1 − Π(1 − α_i)),
// so the optical depth alone decides the pixel. Colours are written linearly (no gamma).
//
// When the fluid reports its domain (FluidSolver::domain()) and `walls` is on, its walls
// (DomainWalls: the floor with a grid, the other closed sides faint, open sides not at
// all) stand where the background would: behind everything in the box, smoke absorbed in
// front of them like anything else. The box's edges are drawn over them, hidden by any
// water or shell nearer to the eye; an edge covering a fraction a of a pixel at ray
// parameter s_e gives (1 − a) · pixel + a · (smoke_colour (1 − T_e) + T_e · grid_colour)
// with T_e the transmittance up to s_e: the same front-to-back compositing with the edge as
// one more layer. The floor is darkened by the shadow the water and smoke cast on it from
// a light straight above (FloorShadow, computed per frame from the fields), so that water
// in mid-air shows where it is above the floor.
// The walls are opaque: the part of a shell beyond a far wall, outside the fluid's box, is
// hidden like anything else behind a wall.

#include <Eigen/Core>
#include <memory>
#include <mutex>
#include <string>

#include "shellflow/preview_writer/camera.hpp"
#include "shellflow/preview_writer/domain_walls.hpp"
#include "shellflow/preview_writer/floor_shadow.hpp"
#include "shellflow/preview_writer/rgb_image.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::preview_writer {

struct PreviewSettings {
  Eigen::Vector3d camera_position{0.0, 1.0, 4.0};
  Eigen::Vector3d look_at{0.0, 0.5, 0.0};
  Eigen::Vector3d up{0.0, 1.0, 0.0};
  double vertical_fov_deg = 45.0;
  int width = 480;
  int height = 360;
  double absorption = 4.0;   ///< σ [1/m per unit density]
  double step_voxels = 0.5;  ///< march step h in units of the field's dx
  Eigen::Vector3d smoke_color{0.92, 0.92, 0.95};
  Eigen::Vector3d background_color{0.10, 0.11, 0.14};
  Eigen::Vector3d shell_color{0.85, 0.55, 0.30};
  double ambient = 0.2;  ///< shade of a shell seen edge-on, as a fraction of its colour
  std::string density_field = "density";
  Eigen::Vector3d water_color{0.10, 0.35, 0.65};
  Eigen::Vector3d water_rim_color{0.80, 0.90, 1.00};  ///< what grazing rays reflect
  std::string water_field = "phi";                    ///< level set, φ ≤ 0 water
  bool walls = true;  ///< draw the fluid domain's walls (DomainWalls)
  WallColours wall_colours;
  double floor_shadow = 0.5;  ///< the floor's colour × (1 − floor_shadow) in full shadow
  /// Gravity's direction: the floor is the wall it points into. Not a parameter: the
  /// writer takes it from the scene (or the camera's down when the scene has no gravity).
  Eigen::Vector3d down{0.0, -1.0, 0.0};
};

/// Schlick's Fresnel term for water seen at |n·d| = cos_theta (see above).
double water_fresnel(double cos_theta);
/// The water's shade for unit normal n seen along unit ray direction d (see above).
Eigen::Vector3d water_shade(const PreviewSettings& settings, const Eigen::Vector3d& normal,
                            const Eigen::Vector3d& direction);

class PreviewRenderer {
 public:
  /// @throw std::invalid_argument for a bad camera (see Camera).
  explicit PreviewRenderer(const PreviewSettings& settings);

  /// Renders `frame` (shells only when it has no fluid or neither a density nor a level
  /// set field; the fluid only when it has no shells). The level set is marched with step
  /// min(step_voxels, 1/2) dx. Rows in parallel (OpenMP). With `walls` on and a fluid
  /// that reports its domain, the walls too (traced on the first frame of a domain, kept
  /// for the next frames with the same domain).
  /// @throw Error when the density or the level set field is not a scalar field, or the
  /// domain box is empty.
  RgbImage render(const sdk::FrameView& frame) const;

  const PreviewSettings& settings() const { return m_settings; }
  const Camera& camera() const { return m_camera; }

  /// The walls of `domain` for this camera: the kept ones when the domain is the same.
  std::shared_ptr<const DomainWalls> walls(const sdk::DomainView& domain) const;

 private:
  PreviewSettings m_settings;
  Camera m_camera;
  mutable std::mutex m_walls_mutex;  ///< guards m_walls (render() may run concurrently)
  mutable std::shared_ptr<const DomainWalls> m_walls;
};

}  // namespace shellflow::preview_writer
