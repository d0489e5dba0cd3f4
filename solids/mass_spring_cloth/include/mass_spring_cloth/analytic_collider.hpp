#pragma once
// Static analytic colliders given in the cloth's parameters: a half-space (plane), a
// solid sphere and a solid axis-aligned box, each as a signed distance with its gradient.

#include <Eigen/Core>

namespace shellflow::cloth {

class AnalyticCollider {
 public:
  enum class Shape { Plane, Sphere, Box };

  /// Half-space below the plane through `point` with normal `normal` (cloth stays above).
  static AnalyticCollider plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);
  static AnalyticCollider sphere(const Eigen::Vector3d& centre, double radius);
  static AnalyticCollider box(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner);

  /// Signed distance [m] (negative inside) and its gradient (the outward normal) at x.
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const;
  Shape shape() const { return m_shape; }

 private:
  Shape m_shape = Shape::Plane;
  Eigen::Vector3d m_a = Eigen::Vector3d::Zero();  ///< plane point, sphere centre, box min
  Eigen::Vector3d m_b = Eigen::Vector3d::Zero();  ///< plane normal, -, box max
  double m_radius = 0.0;
};

}  // namespace shellflow::cloth
