#pragma once
// A triangle clipped by axis-aligned planes into the cells of a grid: the pieces of a shell
// that each cell holds (the §5.1 force on a rigid body's faces; each part's share of a
// moving shell's flux in a cut cell). Sutherland–Hodgman, one plane at a time; a convex
// polygon gains at most one corner per plane, so a triangle in a box has at most nine.

#include <array>

#include <Eigen/Core>

#include "shellflow/geometry/triangle_mesh.hpp"

namespace shellflow::geometry {

struct ConvexPolygon {
  std::array<Eigen::Vector3d, 9> corner;
  int count = 0;

  static ConvexPolygon triangle(const TriangleCorners& c) {
    ConvexPolygon p;
    p.count = 3;
    for (int v = 0; v < 3; ++v) p.corner[v] = c[v];
    return p;
  }
};

/// The part of `in` with sign · (x[axis] − plane) >= 0.
ConvexPolygon clip(const ConvexPolygon& in, int axis, double plane, double sign);

/// The part of `in` inside the box [lo, hi] (on its faces included).
ConvexPolygon clip_to_box(const ConvexPolygon& in, const Eigen::Vector3d& lo,
                          const Eigen::Vector3d& hi);

/// A planar polygon's area and centroid (the fan from its first corner); area 0 for fewer
/// than three corners.
struct PolygonMoments {
  double area = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};
PolygonMoments moments(const ConvexPolygon& polygon);

}  // namespace shellflow::geometry
