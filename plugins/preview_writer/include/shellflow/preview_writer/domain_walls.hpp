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
//
// Defined in this header rather than a .cpp of its own: the plugin's source list
// (CMakeLists.txt) is frozen while the test targets are restructured; move the
// definitions to src/domain_walls.cpp once it can take a file.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
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

// ---------------------------------------------------------------------------------------
// Definitions (see the note at the top).

inline int floor_side(const Eigen::Vector3d& down) {
  if (!(down.norm() > 0.0) || !down.allFinite())
    throw std::invalid_argument("the direction of gravity is zero or not finite");
  int axis = 0;
  down.cwiseAbs().maxCoeff(&axis);
  return 2 * axis + (down[axis] > 0.0 ? 1 : 0);
}

inline double grid_spacing(double length) {
  const double target = length / 10.0;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  double spacing = decade;
  // 1.0000001: a target that is a round number up to round-off keeps its spacing.
  for (double m : {2.0, 5.0, 10.0})
    if (m * decade <= target * (1.0 + 1e-7)) spacing = m * decade;
  return spacing;
}

inline DomainWalls::DomainWalls(const sdk::DomainView& domain, const Eigen::Vector3d& down,
                                const WallColours& colours, const Camera& camera)
    : m_domain(domain), m_colours(colours), m_camera(camera) {
  using Side = sdk::DomainView::Side;
  if (!((domain.upper - domain.lower).array() > 0.0).all())
    throw std::invalid_argument("the fluid's domain box is empty");
  const int floor = floor_side(down);
  if (domain.sides[floor] == Side::Wall) {
    m_floor = floor;
    const int a = floor / 2;
    const Eigen::Vector3d extent = domain.upper - domain.lower;
    m_spacing = grid_spacing(std::max(extent[(a + 1) % 3], extent[(a + 2) % 3]));
  }
  // The 12 edges, each along axis c where the faces (a, sa) and (b, sb) meet; drawn when
  // either face is a wall.
  for (int c = 0; c < 3; ++c) {
    const int a = (c + 1) % 3;
    const int b = (c + 2) % 3;
    for (int sa = 0; sa < 2; ++sa)
      for (int sb = 0; sb < 2; ++sb) {
        if (domain.side(a, sa) != Side::Wall && domain.side(b, sb) != Side::Wall) continue;
        Edge e;
        e.start = domain.lower;
        e.start[a] = sa ? domain.upper[a] : domain.lower[a];
        e.start[b] = sb ? domain.upper[b] : domain.lower[b];
        e.along = Eigen::Vector3d::Unit(c);
        e.length = domain.upper[c] - domain.lower[c];
        m_edges.push_back(e);
      }
  }
  const int width = camera.width();
  const int height = camera.height();
  m_pixels.resize(static_cast<size_t>(width) * height);
  // Serial: once per camera and domain (36 ms for 480 x 360 pixels on one core).
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) m_pixels[static_cast<size_t>(x) + width * y] = trace(x, y);
}

inline WallPixel DomainWalls::trace(int x, int y) const {
  const Ray ray = m_camera.pixel_ray(x, y);
  const Eigen::Vector3d& o = ray.origin;
  const Eigen::Vector3d& d = ray.direction;
  const double depth_per_distance = d.dot(m_camera.forward());  // > 0: inside the frustum
  const double pixel = m_camera.pixel_size();
  WallPixel out;

  // The side the ray leaves the box through (slab test, Kay–Kajiya 1986).
  double s_in = -std::numeric_limits<double>::infinity();
  double s_out = std::numeric_limits<double>::infinity();
  int exit_side = -1;
  bool misses = false;
  for (int a = 0; a < 3 && !misses; ++a) {
    if (d[a] == 0.0) {
      misses = o[a] < m_domain.lower[a] || o[a] > m_domain.upper[a];
      continue;
    }
    const double t_lower = (m_domain.lower[a] - o[a]) / d[a];
    const double t_upper = (m_domain.upper[a] - o[a]) / d[a];
    s_in = std::max(s_in, std::min(t_lower, t_upper));
    const double far = std::max(t_lower, t_upper);
    if (far < s_out) {
      s_out = far;
      exit_side = 2 * a + (d[a] > 0.0 ? 1 : 0);
    }
  }
  if (!misses && exit_side >= 0 && s_in <= s_out && s_out > 0.0 &&
      m_domain.sides[exit_side] == sdk::DomainView::Side::Wall) {
    out.distance = s_out;
    out.floor = exit_side == m_floor;
    const Eigen::Vector3d p = o + s_out * d;
    out.colour = out.floor ? floor_colour(p, d / depth_per_distance, s_out * depth_per_distance)
                           : m_colours.wall;
  }

  // Edges: the closest approach of the ray and each segment; a pixel-wide tent.
  for (const Edge& e : m_edges) {
    const Eigen::Vector3d w0 = o - e.start;
    const double b = d.dot(e.along);
    const double dw = d.dot(w0);
    const double ew = e.along.dot(w0);
    const double denom = 1.0 - b * b;
    // Parallel within round-off: any point of the segment is as near; take its start.
    double along = denom > 1e-12 ? (ew - b * dw) / denom : 0.0;
    along = std::clamp(along, 0.0, e.length);
    const Eigen::Vector3d q = e.start + along * e.along;
    const double s = (q - o).dot(d);
    if (!(s > 0.0)) continue;
    const double miss = (o + s * d - q).norm();
    const double pixel_width = s * depth_per_distance * pixel;  // lateral size of a pixel
    const double alpha = std::clamp(1.0 - miss / pixel_width, 0.0, 1.0);
    if (alpha > out.edge_alpha) {
      out.edge_alpha = alpha;
      out.edge_distance = s;
    }
  }
  return out;
}

inline Eigen::Vector3d DomainWalls::floor_colour(const Eigen::Vector3d& p,
                                                 const Eigen::Vector3d& view, double t) const {
  const int a = m_floor / 2;
  // How p moves on the floor per pixel: p = o + t D with t = n·(p0 − o) / (n·D), so
  // dp = t (dD − D (n·dD) / (n·D)), with dD = pixel · right (x) and −pixel · up (y).
  const double pixel = m_camera.pixel_size();
  const Eigen::Vector3d step_x = pixel * m_camera.right();
  const Eigen::Vector3d step_y = -pixel * m_camera.up();
  const Eigen::Vector3d dp_x = t * (step_x - view * (step_x[a] / view[a]));
  const Eigen::Vector3d dp_y = t * (step_y - view * (step_y[a] / view[a]));
  double uncovered = 1.0;
  for (int u : {(a + 1) % 3, (a + 2) % 3}) {
    // |∇u| on the screen: the change of coordinate u [m] per pixel.
    const double per_pixel = std::hypot(dp_x[u], dp_y[u]);
    const double c = p[u] / m_spacing;
    const double to_line = m_spacing * std::abs(c - std::round(c));      // [m]
    const double lines_apart = m_spacing / std::max(per_pixel, 1e-300);  // [px]
    const double cover = std::clamp(1.0 - to_line / std::max(per_pixel, 1e-300), 0.0, 1.0);
    // A tent of radius 1 px covers 1 px per period on average: 1/8 at kSharpLines apart.
    const double fade =
        std::clamp((lines_apart - kFadedLines) / (kSharpLines - kFadedLines), 0.0, 1.0);
    uncovered *= 1.0 - (fade * cover + (1.0 - fade) / kSharpLines);
  }
  return m_colours.floor + (1.0 - uncovered) * (m_colours.grid - m_colours.floor);
}

}  // namespace shellflow::preview_writer
