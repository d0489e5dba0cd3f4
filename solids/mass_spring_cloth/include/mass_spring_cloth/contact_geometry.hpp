#pragma once
// Distance and continuous-collision primitives for cloth contact (Bridson, Fedkiw,
// Anderson, "Robust Treatment of Collisions, Contact and Friction for Cloth Animation",
// SIGGRAPH 2002, §6): closest points point–triangle and segment–segment, and the times
// in [0, 1] at which four linearly moving points become coplanar (a cubic).

#include <Eigen/Core>
#include <array>

namespace shellflow::cloth {

/// Closest point of triangle (a, b, c) to p, as barycentric weights (Ericson 2005, §5.1.5).
Eigen::Vector3d closest_point_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Closest points of segments p0-p1 and q0-q1: parameters (s, t) in [0, 1]^2.
Eigen::Vector2d closest_points_segments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1);

/// Times t in [0, 1], increasing, where x0 + t v0, ..., x3 + t v3 are coplanar; returns the
/// count. `x` start positions, `d` displacements over the step. Roots are isolated between
/// the cubic's critical points and refined by bisection.
int coplanarity_times(const std::array<Eigen::Vector3d, 4>& x,
                      const std::array<Eigen::Vector3d, 4>& d, std::array<double, 3>& times);

}  // namespace shellflow::cloth
