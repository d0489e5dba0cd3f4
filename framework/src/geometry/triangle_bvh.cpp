#include "shellflow/geometry/triangle_bvh.hpp"

#include <limits>

namespace shellflow::geometry {

TriangleBvh::TriangleBvh(const TriangleMesh& mesh, double max_degradation)
    : m_mesh(mesh), m_max_degradation(max_degradation) {
  m_mesh.boxes(m_boxes);
  m_bvh.build(m_boxes);
  prepare();
}

void TriangleBvh::prepare() {
  m_prepared.resize(m_mesh.triangle_count());
  for (int t = 0; t < m_mesh.triangle_count(); ++t) {
    m_prepared[t] = PreparedTriangle(m_mesh.corners(t));
  }
}

bool TriangleBvh::update(const TriangleMesh& mesh) {
  if (!mesh.same_topology(m_mesh) && m_mesh.triangle_count() != 0) {
    throw Error("TriangleBvh::update: the mesh topology changed; construct a new TriangleBvh");
  }
  m_mesh = mesh;
  m_mesh.boxes(m_boxes);
  prepare();
  return m_bvh.refit_or_rebuild(m_boxes, m_max_degradation);
}

SurfacePoint TriangleBvh::closest_point(const Eigen::Vector3d& p) const {
  return closest_point(p, std::numeric_limits<double>::infinity());
}

SurfacePoint TriangleBvh::closest_point(const Eigen::Vector3d& p, double max_distance) const {
  SurfacePoint result;
  const double limit2 = max_distance * max_distance;
  int best = -1;
  TrianglePoint best_point{};
  const double best2 = m_bvh.nearest(
      [&](const Aabb& box) {
        const double d2 = box.squared_distance(p);
        return d2 > limit2 ? std::numeric_limits<double>::infinity() : d2;
      },
      [&](int t, double bound2) {
        if (m_boxes[t].squared_distance(p) >= bound2) return bound2;
        const TrianglePoint cp = closest_point_on_triangle(p, m_mesh.corners(t));
        const double d2 = (cp.point - p).squaredNorm();
        if (d2 < bound2 && d2 <= limit2) {
          best_point = cp;
          return d2;
        }
        return bound2;
      },
      best);
  if (best < 0) return result;
  result.triangle = best;
  result.distance2 = best2;
  result.point = best_point.point;
  result.barycentric = best_point.barycentric;
  return result;
}

}  // namespace shellflow::geometry
