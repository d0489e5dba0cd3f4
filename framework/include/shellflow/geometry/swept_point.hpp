#pragma once
// Swept-point test (§3, after Bridson, Fedkiw, Anderson 2002): does a triangle whose
// corners move linearly from x^n to x^{n+1} over the step pass through a fixed point p?
//
// With y_i(t) = x_i(t) - p, the point and the triangle are coplanar when
//   f(t) = det[y0, y1, y2] = -(x1 - x0) x (x2 - x0) · (p - x0) = 0,
// a cubic in t (f = -|n(t)| × signed distance of p to the plane). Its roots in [0, 1]
// are isolated robustly (cubic_near_roots) and at each the inside-triangle test is done
// with a distance tolerance. When f vanishes on the whole step (p stays in the plane:
// in-plane motion, or a zero-area triangle), p can only enter the triangle across an
// edge or a vertex, so the times where p is on an edge line (each component of
// y_i x y_j, a quadratic) and the closest approach of each vertex are checked instead.

#include <optional>

#include "shellflow/geometry/cubic_roots.hpp"
#include "shellflow/geometry/triangle_mesh.hpp"

namespace shellflow::geometry {

/// Coefficients (c0..c3) of f(t) = det[x0(t) - p, x1(t) - p, x2(t) - p].
std::array<double, 4> coplanarity_cubic(const Eigen::Vector3d& p, const TriangleCorners& start,
                                        const TriangleCorners& end);

/// The earliest time t in [0, 1] at which p lies within `tolerance` of the moving
/// triangle at a (near-)coplanarity time, or nothing. `tolerance` is a length (> 0):
/// a bit above the round-off of the positions, far below the wedge thickness.
std::optional<double> triangle_sweeps_point(const Eigen::Vector3d& p, const TriangleCorners& start,
                                            const TriangleCorners& end, double tolerance);

/// §3 invalidation of one point by one triangle: swept during the step, or inside the
/// triangle's wedge (distance <= epsilon / 2) at the start or at the end of the step.
bool point_invalidated(const Eigen::Vector3d& p, const TriangleCorners& start,
                       const TriangleCorners& end, double epsilon, double tolerance);

}  // namespace shellflow::geometry
