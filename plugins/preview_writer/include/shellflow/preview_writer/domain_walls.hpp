#pragma once
// DomainWalls: the fluid's domain box as a preview draws it, so that a pool on the floor
// and a sheet of water in mid-air look different.
//
// What is drawn, and why:
//  - Only the closed sides (sdk::DomainView::Side::Wall). Open and inflow sides are where
//    the fluid crosses the box: nothing is there, and a face or a dashed line would read as
//    a wall.
//  - Each wall as seen from inside the box (a cutaway): a pixel shows the wall through which
//    its ray leaves the box, never one it enters through, which would hide what is inside.
//    The walls are therefore behind all the water, smoke and shells in the box; the
//    renderer puts them where the background would be.
//  - The floor, the wall that gravity points into (the face whose outward normal is nearest
//    to `down`), in floor colour with a grid in grid colour: lines on the multiples of a
//    spacing of 1, 2 or 5 × 10^k m (10 to 25 squares along the floor's longer side), so that
//    the squares measure positions. Lines are about a pixel wide, antialiased (a tent of
//    one pixel's radius); where lines come closer than 8 pixels they fade into the flat
//    tone they have on average at 8 pixels apart, reached at 4: no moiré where the floor is
//    seen at a grazing angle, and the far floor keeps the near floor's brightness.
//  - The other walls flat in wall colour, just off the background.
//  - The box's edges that border a wall, a pixel wide in grid colour, at their depth: the
//    renderer draws them over the walls and behind any water or shell nearer to the eye,
//    so the near edges outline the box without hiding what is in it.
// Nothing is lit: faint, flat colours keep the walls from competing with the water.
//
// Cost: all of this depends on the camera and the domain only, so the constructor traces
// every pixel once and a frame reads one WallPixel per pixel (the renderer keeps the object
// while the domain stays the same).

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <vector>

#include "shellflow/preview_writer/camera.hpp"
#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

/// Floor grid lines this many pixels apart or more are drawn sharp (DomainWalls).
constexpr double kSharpLines = 8.0;
/// ... and this many or fewer are a flat tone, their mean at kSharpLines apart.
constexpr double kFadedLines = 4.0;

struct WallColours {
  Eigen::Vector3d floor{0.20, 0.20, 0.21};
  Eigen::Vector3d grid{0.34, 0.34, 0.36};
  Eigen::Vector3d wall{0.14, 0.15, 0.18};
};

/// What the walls put into one pixel.
struct WallPixel {
  /// Ray parameter [m] where the ray leaves the box through a wall; inf when it leaves
  /// through an open or inflow side, or misses the box.
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d colour = Eigen::Vector3d::Zero();  ///< that wall's colour there
  bool floor = false;                                ///< that wall is the floor
  /// Ray parameter [m] of the nearest point of the box edge that covers the pixel most.
  double edge_distance = std::numeric_limits<double>::infinity();
  double edge_alpha = 0.0;  ///< how much of the pixel that edge covers, in [0, 1]

  bool wall() const { return distance < std::numeric_limits<double>::infinity(); }
};

/// The side (2 axis + max_side) whose outward normal is nearest to `down`: the floor.
/// @throw std::invalid_argument when `down` is zero or not finite.
int floor_side(const Eigen::Vector3d& down);

/// The grid spacing for a floor whose longer side is `length`: the largest of
/// 1, 2, 5 × 10^k not above length / 10.
double grid_spacing(double length);

class DomainWalls {
 public:
  /// Traces every pixel of `camera` against `domain`'s box. `down`: gravity's direction.
  /// @throw std::invalid_argument for an empty box or a zero `down`.
  DomainWalls(const sdk::DomainView& domain, const Eigen::Vector3d& down,
              const WallColours& colours, const Camera& camera);

  /// What the walls put into pixel (x, y) (stored by the constructor).
  const WallPixel& pixel(int x, int y) const {
    return m_pixels[static_cast<size_t>(x) + static_cast<size_t>(m_camera.width()) * y];
  }
  /// The same, computed: the ray of pixel (x, y) against the walls and edges.
  WallPixel trace(int x, int y) const;

  const sdk::DomainView& domain() const { return m_domain; }
  /// The floor's side (floor_side(down)); -1 when that side is not a wall.
  int floor() const { return m_floor; }
  /// Distance between the floor's grid lines [m] (0 without a floor).
  double spacing() const { return m_spacing; }

 private:
  struct Edge {
    Eigen::Vector3d start;
    Eigen::Vector3d along;  ///< unit
    double length = 0.0;
  };
  /// The floor's colour at point p, hit along unnormalised direction `view` (pixel_ray's
  /// forward + sx right + sy up) at `t` times it.
  Eigen::Vector3d floor_colour(const Eigen::Vector3d& p, const Eigen::Vector3d& view,
                               double t) const;

  sdk::DomainView m_domain;
  WallColours m_colours;
  Camera m_camera;
  int m_floor = -1;
  double m_spacing = 0.0;
  std::vector<Edge> m_edges;
  /// Pixel (x, y) at x + width y, as RgbImage. One record per pixel rather than one array
  /// per field: the renderer reads all of a pixel's fields together, once per frame.
  std::vector<WallPixel> m_pixels;
};

}  // namespace shellflow::preview_writer
