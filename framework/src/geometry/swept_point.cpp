#include "shellflow/geometry/swept_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/geometry/triangle_distance.hpp"

namespace shellflow::geometry {

namespace {

/// Round-off floor of the polynomial tolerances: a degree-3 product of coordinates of
/// size Y carries an error of a few ulps × Y^3; 64 ulps leaves margin.
constexpr double kRoundOffUlps = 64.0 * std::numeric_limits<double>::epsilon();

TriangleCorners at_time(const TriangleCorners& start, const TriangleCorners& end, double t) {
  return {(1.0 - t) * start[0] + t * end[0], (1.0 - t) * start[1] + t * end[1],
          (1.0 - t) * start[2] + t * end[2]};
}

}  // namespace

std::array<double, 4> coplanarity_cubic(const Eigen::Vector3d& p, const TriangleCorners& start,
                                        const TriangleCorners& end) {
  // y_i(t) = a_i + t v_i; det[y0, y1, y2] = y0 · (y1 × y2) expanded in powers of t.
  const Eigen::Vector3d a0 = start[0] - p, a1 = start[1] - p, a2 = start[2] - p;
  const Eigen::Vector3d v0 = end[0] - start[0], v1 = end[1] - start[1], v2 = end[2] - start[2];
  const Eigen::Vector3d a1xa2 = a1.cross(a2);
  const Eigen::Vector3d v1xv2 = v1.cross(v2);
  const Eigen::Vector3d a1xv2 = a1.cross(v2);
  const Eigen::Vector3d v1xa2 = v1.cross(a2);
  return {a0.dot(a1xa2), v0.dot(a1xa2) + a0.dot(v1xa2 + a1xv2),
          a0.dot(v1xv2) + v0.dot(v1xa2 + a1xv2), v0.dot(v1xv2)};
}

std::optional<double> triangle_sweeps_point(const Eigen::Vector3d& p, const TriangleCorners& start,
                                            const TriangleCorners& end, double tolerance) {
  double scale = 0.0;  // largest |x_i - p| over both ends
  double edge = 0.0;   // longest edge over both ends
  for (int i = 0; i < 3; ++i) {
    scale = std::max({scale, (start[i] - p).norm(), (end[i] - p).norm()});
    edge = std::max(
        {edge, (start[(i + 1) % 3] - start[i]).norm(), (end[(i + 1) % 3] - end[i]).norm()});
  }
  const double floor3 = kRoundOffUlps * scale * scale * scale;
  const double floor2 = kRoundOffUlps * scale * scale;

  // |f| <= tolerance |n| means p within `tolerance` of the plane; |n(t)| sampled at both
  // ends and the middle (it is a quadratic; this only sets which times are candidates).
  double normal = 0.0;
  for (const double t : {0.0, 0.5, 1.0}) {
    const TriangleCorners c = at_time(start, end, t);
    normal = std::max(normal, (c[1] - c[0]).cross(c[2] - c[0]).norm());
  }
  const NearRoots roots =
      cubic_near_roots(coplanarity_cubic(p, start, end), tolerance * normal + floor3);

  // At most 12 cubic times + 2 ends + 3 edges × (3 components × 12 + 1 vertex) = 125.
  double candidates[128];
  int count = 0;
  for (int i = 0; i < roots.count; ++i) candidates[count++] = roots.times[i];
  if (roots.everywhere_near_zero) {
    // p stays in the plane: it enters the triangle across an edge line or at a vertex.
    candidates[count++] = 0.0;
    candidates[count++] = 1.0;
    for (int e = 0; e < 3; ++e) {
      const int i = e;
      const int j = (e + 1) % 3;
      const Eigen::Vector3d ai = start[i] - p, aj = start[j] - p;
      const Eigen::Vector3d vi = end[i] - start[i], vj = end[j] - start[j];
      // y_i × y_j = |edge| × distance of p to the edge line; zero when p is on it.
      const Eigen::Vector3d w0 = ai.cross(aj);
      const Eigen::Vector3d w1 = ai.cross(vj) + vi.cross(aj);
      const Eigen::Vector3d w2 = vi.cross(vj);
      for (int k = 0; k < 3; ++k) {
        const NearRoots edge_roots =
            cubic_near_roots({w0[k], w1[k], w2[k], 0.0}, tolerance * edge + floor2);
        if (edge_roots.everywhere_near_zero) continue;  // this component says nothing
        for (int r = 0; r < edge_roots.count; ++r) {
          candidates[count++] = edge_roots.times[r];
        }
      }
      // Closest approach of vertex i to p.
      const double vv = vi.squaredNorm();
      if (vv > 0.0) candidates[count++] = std::clamp(-ai.dot(vi) / vv, 0.0, 1.0);
    }
  }
  std::sort(candidates, candidates + count);
  const double tolerance2 = tolerance * tolerance;
  for (int i = 0; i < count; ++i) {
    if (point_triangle_distance2(p, at_time(start, end, candidates[i])) <= tolerance2) {
      return candidates[i];
    }
  }
  return std::nullopt;
}

bool point_invalidated(const Eigen::Vector3d& p, const TriangleCorners& start,
                       const TriangleCorners& end, double epsilon, double tolerance) {
  const double r2 = 0.25 * epsilon * epsilon;
  if (point_triangle_distance2(p, start) <= r2) return true;
  if (point_triangle_distance2(p, end) <= r2) return true;
  return triangle_sweeps_point(p, start, end, tolerance).has_value();
}

}  // namespace shellflow::geometry
