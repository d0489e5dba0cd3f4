#include "mass_spring_cloth/analytic_collider.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::cloth {

AnalyticCollider AnalyticCollider::plane(const Eigen::Vector3d& point,
                                         const Eigen::Vector3d& normal) {
  AnalyticCollider c;
  c.m_shape = Shape::Plane;
  c.m_a = point;
  c.m_b = normal.normalized();
  return c;
}

AnalyticCollider AnalyticCollider::sphere(const Eigen::Vector3d& centre, double radius) {
  AnalyticCollider c;
  c.m_shape = Shape::Sphere;
  c.m_a = centre;
  c.m_radius = radius;
  return c;
}

AnalyticCollider AnalyticCollider::box(const Eigen::Vector3d& min_corner,
                                       const Eigen::Vector3d& max_corner) {
  AnalyticCollider c;
  c.m_shape = Shape::Box;
  c.m_a = min_corner.cwiseMin(max_corner);
  c.m_b = min_corner.cwiseMax(max_corner);
  return c;
}

double AnalyticCollider::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const {
  switch (m_shape) {
    case Shape::Plane:
      normal = m_b;
      return (x - m_a).dot(m_b);
    case Shape::Sphere: {
      const Eigen::Vector3d d = x - m_a;
      const double r = d.norm();
      normal = r > 0.0 ? Eigen::Vector3d(d / r) : Eigen::Vector3d::UnitY();
      return r - m_radius;
    }
    case Shape::Box: {
      const Eigen::Vector3d centre = 0.5 * (m_a + m_b), half = 0.5 * (m_b - m_a);
      const Eigen::Vector3d p = x - centre;
      const Eigen::Vector3d q = p.cwiseAbs() - half;
      if (q.maxCoeff() > 0.0) {  // outside: distance to the nearest box point
        const Eigen::Vector3d outside = q.cwiseMax(0.0);
        const double dist = outside.norm();
        for (int k = 0; k < 3; ++k) normal[k] = std::copysign(outside[k], p[k]);
        normal /= dist;
        return dist;
      }
      int axis = 0;  // inside: through the nearest face
      q.maxCoeff(&axis);
      normal = Eigen::Vector3d::Zero();
      normal[axis] = p[axis] >= 0.0 ? 1.0 : -1.0;
      return q[axis];
    }
  }
  return 0.0;
}

}  // namespace shellflow::cloth
