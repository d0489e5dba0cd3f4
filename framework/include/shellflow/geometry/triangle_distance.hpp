#pragma once
// Exact closest points between points, segments and triangles (Ericson, "Real-Time
// Collision Detection" 2005, §5.1.2, §5.1.5, §5.1.9), written to stay finite for
// degenerate input (zero-length segments, zero-area triangles). These are the
// primitives of the thickened-wedge ray casts (§3, Fig. 3) and of the swept-point test.

#include <Eigen/Geometry>

#include "shellflow/geometry/triangle_mesh.hpp"

namespace shellflow::geometry {

/// Closest point on segment [a, b] to p; `s` in [0, 1] its parameter.
Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, double& s);

/// Closest point of a triangle to a point, with its barycentric coordinates.
struct TrianglePoint {
  Eigen::Vector3d point;
  Eigen::Vector3d barycentric;  ///< weights of corners 0, 1, 2 (sum 1, each >= 0)
};
/// Exact for non-degenerate triangles (Ericson §5.1.5); a zero-area triangle is treated as
/// the union of its three edges.
TrianglePoint closest_point_on_triangle(const Eigen::Vector3d& p, const TriangleCorners& c);

/// Closest pair between segments [p0, p1] and [q0, q1] (Ericson §5.1.9).
struct SegmentSegmentClosest {
  double distance2;  ///< squared distance
  double s;          ///< parameter on [p0, p1]
  double t;          ///< parameter on [q0, q1]
};
SegmentSegmentClosest closest_segment_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                              const Eigen::Vector3d& q0, const Eigen::Vector3d& q1);

/// Closest pair between segment [a, b] and a triangle.
struct SegmentTriangleClosest {
  double distance2;             ///< squared distance
  double s;                     ///< parameter on [a, b] of the segment's closest point
  Eigen::Vector3d barycentric;  ///< the triangle's closest point
};
/// The minimum over: the plane crossing point (when the segment crosses the plane), both
/// endpoints against the triangle, and the segment against the three edges. For two
/// convex sets this covers every place a minimum can sit: if neither closest point is on
/// a boundary (an endpoint or an edge) the segment crosses the triangle or is parallel to
/// it, and in the parallel case the same distance is reached at a boundary too.
SegmentTriangleClosest closest_segment_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                const TriangleCorners& c);

/// Is segment [a, b] within distance r of the triangle, i.e. does it touch the triangle
/// thickened by r (the ±r slab over the face plus the r-capsules around the edges and the
/// r-balls at the vertices)? Starts with the cheap plane-slab rejection.
bool segment_near_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const TriangleCorners& c, double r);

/// A triangle with its plane precomputed for repeated wedge tests (§3, Fig. 3).
struct PreparedTriangle {
  TriangleCorners corners;
  /// Unit normal of (c1 - c0) x (c2 - c0); zero when the triangle is degenerate (its
  /// normal is round-off), and then no plane test is made.
  Eigen::Vector3d unit_normal = Eigen::Vector3d::Zero();
  bool degenerate = true;

  PreparedTriangle() = default;
  explicit PreparedTriangle(const TriangleCorners& c);

  /// Signed distance of p to the triangle's plane (0 for a degenerate triangle).
  double plane_distance(const Eigen::Vector3d& p) const { return unit_normal.dot(p - corners[0]); }
  /// Plane-slab rejection: are both a and b farther than r from the plane, on the same
  /// side? Then the segment is farther than r from the triangle. Exact for any plane
  /// through the triangle, so never true for a degenerate one.
  bool slab_separates(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r) const {
    if (degenerate) return false;
    const double da = plane_distance(a);
    const double db = plane_distance(b);
    return (da > r && db > r) || (da < -r && db < -r);
  }
};

/// segment_near_triangle for a prepared triangle: the plane-slab rejection, then a quick
/// accept when the segment crosses the plane inside the triangle (distance 0), then the
/// exact closest-pair distance.
bool segment_near_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const PreparedTriangle& t, double r);

/// Squared distance of p to the triangle.
inline double point_triangle_distance2(const Eigen::Vector3d& p, const TriangleCorners& c) {
  return (closest_point_on_triangle(p, c).point - p).squaredNorm();
}

}  // namespace shellflow::geometry
