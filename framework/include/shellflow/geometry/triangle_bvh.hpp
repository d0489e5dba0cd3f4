#pragma once
// TriangleBvh: the box hierarchy of one shell's triangles at one instant (§3), with the
// queries the fluid needs: triangles near a segment, triangles overlapping a box, and the
// closest point on the surface. update() refits after node motion and rebuilds when the
// refit tree has degraded (Bvh::refit_or_rebuild). It also keeps each triangle's
// corners and unit normal (PreparedTriangle), refreshed by update(), so that the wedge
// tests read one record instead of gathering nodes and recomputing the plane per query.

#include <vector>

#include "shellflow/geometry/bvh.hpp"
#include "shellflow/geometry/triangle_distance.hpp"
#include "shellflow/geometry/triangle_mesh.hpp"

namespace shellflow::geometry {

/// The closest surface point to a query point.
struct SurfacePoint {
  int triangle = -1;       ///< -1 when the mesh is empty
  double distance2 = 0.0;  ///< squared distance
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
};

class TriangleBvh {
 public:
  /// Rebuild when the refit SAH cost exceeds this factor times the cost after the last
  /// build. 2 keeps queries within ~2x of a fresh tree; measured in bench_geometry.
  static constexpr double kDefaultMaxDegradation = 2.0;

  TriangleBvh() = default;
  explicit TriangleBvh(const TriangleMesh& mesh, double max_degradation = kDefaultMaxDegradation);

  /// Takes the mesh at new positions (same topology): refit, rebuild if degraded.
  /// Returns true when it rebuilt.
  bool update(const TriangleMesh& mesh);

  const TriangleMesh& mesh() const { return m_mesh; }
  const Bvh& bvh() const { return m_bvh; }
  std::span<const Aabb> boxes() const { return m_boxes; }
  /// Corners and plane of every triangle at the positions of the last build/update.
  std::span<const PreparedTriangle> prepared_triangles() const { return m_prepared; }

  /// Calls visit(triangle) for each triangle whose box, inflated by r, the segment
  /// [a, b] touches; visit returns true to stop. Returns true when stopped.
  template <class Visit>
  bool triangles_near_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                              Visit&& visit) const {
    const SegmentBoxQuery exact(a, b, r);
    return candidates_near_segment(a, b, r, [&](int t) { return exact(m_boxes[t]) && visit(t); });
  }
  /// Like triangles_near_segment, but a conservative superset: every triangle whose box,
  /// inflated by r, the segment touches, plus possibly some it misses by less than
  /// WideSegmentQuery's slack (~4e-6 of the coordinate magnitude). For callers that run
  /// an exact test on each triangle anyway (the wedge caster).
  template <class Visit>
  bool candidates_near_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                               Visit&& visit) const {
    const WideSegmentQuery query(a, b, r, m_bvh.coordinate_scale());
    return m_bvh.traverse_wide(query, visit);
  }
  /// Calls visit(triangle) for each triangle whose box overlaps `box`; visit returns
  /// true to stop. Returns true when stopped.
  template <class Visit>
  bool triangles_overlapping(const Aabb& box, Visit&& visit) const {
    return m_bvh.traverse(
        m_boxes, [&](const Aabb& node) { return node.overlaps(box); }, visit);
  }

  /// Like triangles_overlapping, but a conservative superset: the float boxes of the
  /// compact layout are rounded outward, so a triangle whose box misses `box` by less
  /// than a float rounding (~6e-8 of the coordinates) may be visited too.
  template <class Visit>
  bool candidates_overlapping(const Aabb& box, Visit&& visit) const {
    return m_bvh.traverse_wide(WideBoxQuery(box), visit);
  }

  /// Closest point of the surface to p (branch and bound).
  SurfacePoint closest_point(const Eigen::Vector3d& p) const;
  /// Closest point, searching only within distance `max_distance` (triangle -1 if none).
  SurfacePoint closest_point(const Eigen::Vector3d& p, double max_distance) const;

 private:
  TriangleMesh m_mesh;
  Bvh m_bvh;
  std::vector<Aabb> m_boxes;
  std::vector<PreparedTriangle> m_prepared;
  void prepare();

  double m_max_degradation = kDefaultMaxDegradation;
};

}  // namespace shellflow::geometry
