#include "shellflow/geometry/convex_polygon.hpp"

#include <Eigen/Geometry>

namespace shellflow::geometry {

ConvexPolygon clip(const ConvexPolygon& in, int axis, double plane, double sign) {
  ConvexPolygon out;
  for (int i = 0; i < in.count; ++i) {
    const Eigen::Vector3d& p = in.corner[i];
    const Eigen::Vector3d& q = in.corner[(i + 1) % in.count];
    const double dp = sign * (p[axis] - plane), dq = sign * (q[axis] - plane);
    if (dp >= 0.0) out.corner[out.count++] = p;
    if ((dp >= 0.0) != (dq >= 0.0)) out.corner[out.count++] = p + dp / (dp - dq) * (q - p);
  }
  return out;
}

ConvexPolygon clip_to_box(const ConvexPolygon& in, const Eigen::Vector3d& lo,
                          const Eigen::Vector3d& hi) {
  ConvexPolygon out = in;
  for (int a = 0; a < 3 && out.count >= 3; ++a)
    out = clip(clip(out, a, lo[a], 1.0), a, hi[a], -1.0);
  return out;
}

PolygonMoments moments(const ConvexPolygon& polygon) {
  PolygonMoments m;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  for (int v = 1; v + 1 < polygon.count; ++v) {
    const Eigen::Vector3d& a = polygon.corner[0];
    const Eigen::Vector3d& b = polygon.corner[v];
    const Eigen::Vector3d& c = polygon.corner[v + 1];
    const double w = 0.5 * (b - a).cross(c - a).norm();
    m.area += w;
    first_moment += w * (a + b + c) / 3.0;
  }
  if (m.area > 0.0) m.centroid = first_moment / m.area;
  return m;
}

}  // namespace shellflow::geometry
