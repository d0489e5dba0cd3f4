#include "shellflow/preview_writer/domain_walls.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace shellflow::preview_writer {

int floor_side(const Eigen::Vector3d& down) {
  if (!(down.norm() > 0.0) || !down.allFinite())
    throw std::invalid_argument("the direction of gravity is zero or not finite");
  int axis = 0;
  down.cwiseAbs().maxCoeff(&axis);
  return 2 * axis + (down[axis] > 0.0 ? 1 : 0);
}

double grid_spacing(double length) {
  const double target = length / 10.0;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  double spacing = decade;
  // 1.0000001: a target that is a round number up to round-off keeps its spacing.
  for (double m : {2.0, 5.0, 10.0})
    if (m * decade <= target * (1.0 + 1e-7)) spacing = m * decade;
  return spacing;
}

DomainWalls::DomainWalls(const sdk::DomainView& domain, const Eigen::Vector3d& down,
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

WallPixel DomainWalls::trace(int x, int y) const {
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

Eigen::Vector3d DomainWalls::floor_colour(const Eigen::Vector3d& p, const Eigen::Vector3d& view,
                                          double t) const {
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
