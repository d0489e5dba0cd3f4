#pragma once
// TriangleBvh: the box hierarchy of one shell's triangles at one instant (§3), with the
// queries the fluid needs: triangles near a segment, triangles overlapping a box, and the
// closest point on the surface. update() refits after node motion and rebuilds when the
// refit tree has degraded (Bvh::refit_or_rebuild).

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

  /// Calls visit(triangle) for each triangle whose box, inflated by r, the segment
  /// [a, b] touches; visit returns true to stop. Returns true when stopped.
  template <class Visit>
  bool triangles_near_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                              Visit&& visit) const {
    const SegmentBoxQuery query(a, b, r);
    return m_bvh.traverse(m_boxes, query, visit);
  }
  /// Calls visit(triangle) for each triangle whose box overlaps `box`; visit returns
  /// true to stop. Returns true when stopped.
  template <class Visit>
  bool triangles_overlapping(const Aabb& box, Visit&& visit) const {
    return m_bvh.traverse(
        m_boxes, [&](const Aabb& node) { return node.overlaps(box); }, visit);
  }

  /// Closest point of the surface to p (branch and bound).
  SurfacePoint closest_point(const Eigen::Vector3d& p) const;
  /// Closest point, searching only within distance `max_distance` (triangle -1 if none).
  SurfacePoint closest_point(const Eigen::Vector3d& p, double max_distance) const;

 private:
  TriangleMesh m_mesh;
  Bvh m_bvh;
  std::vector<Aabb> m_boxes;
  double m_max_degradation = kDefaultMaxDegradation;
};

}  // namespace shellflow::geometry
