#include "shellflow/geometry/triangle_distance.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::geometry {

namespace {

/// A triangle whose squared doubled area is below this fraction of (longest edge)^4 is
/// treated as degenerate: its plane normal is then round-off (relative 1e-16 per
/// coordinate gives |n|^2 ~ 1e-32 L^4), so 1e-24 leaves eight orders of margin.
constexpr double kDegenerateRatio = 1e-24;

bool degenerate(const TriangleCorners& c, const Eigen::Vector3d& n) {
  const double l2 = std::max(
      {(c[1] - c[0]).squaredNorm(), (c[2] - c[1]).squaredNorm(), (c[0] - c[2]).squaredNorm()});
  return !(n.squaredNorm() > kDegenerateRatio * l2 * l2);
}

TrianglePoint closest_on_edges(const Eigen::Vector3d& p, const TriangleCorners& c) {
  TrianglePoint best{c[0], {1.0, 0.0, 0.0}};
  double best2 = (p - c[0]).squaredNorm();
  for (int e = 0; e < 3; ++e) {
    const int i = e;
    const int j = (e + 1) % 3;
    double s = 0.0;
    const Eigen::Vector3d q = closest_point_on_segment(p, c[i], c[j], s);
    const double d2 = (q - p).squaredNorm();
    if (d2 < best2) {
      best2 = d2;
      best.point = q;
      best.barycentric.setZero();
      best.barycentric[i] = 1.0 - s;
      best.barycentric[j] = s;
    }
  }
  return best;
}

}  // namespace

Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, double& s) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  s = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return a + s * ab;
}

TrianglePoint closest_point_on_triangle(const Eigen::Vector3d& p, const TriangleCorners& c) {
  const Eigen::Vector3d& a = c[0];
  const Eigen::Vector3d& b = c[1];
  const Eigen::Vector3d& cc = c[2];
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = cc - a;
  if (degenerate(c, ab.cross(ac))) return closest_on_edges(p, c);
  // Ericson §5.1.5: Voronoi regions of the vertices, then the edges, then the face.
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, {1.0, 0.0, 0.0}};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, {0.0, 1.0, 0.0}};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, {1.0 - v, v, 0.0}};
  }
  const Eigen::Vector3d cp = p - cc;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {cc, {0.0, 0.0, 1.0}};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, {1.0 - w, 0.0, w}};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (cc - b), {0.0, 1.0 - w, w}};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  return {a + ab * v + ac * w, {1.0 - v - w, v, w}};
}

SegmentSegmentClosest closest_segment_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                              const Eigen::Vector3d& q0,
                                              const Eigen::Vector3d& q1) {
  // Ericson §5.1.9, with the degenerate (point) cases handled first.
  const Eigen::Vector3d d1 = p1 - p0;
  const Eigen::Vector3d d2 = q1 - q0;
  const Eigen::Vector3d r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0.0;
  double t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    return {r.squaredNorm(), 0.0, 0.0};
  }
  if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;  // >= 0; 0 when parallel
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {(p0 + s * d1 - q0 - t * d2).squaredNorm(), s, t};
}

SegmentTriangleClosest closest_segment_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                const TriangleCorners& c) {
  SegmentTriangleClosest best{std::numeric_limits<double>::infinity(), 0.0, {1.0, 0.0, 0.0}};
  const auto consider = [&best](double d2, double s, const Eigen::Vector3d& bary) {
    if (d2 < best.distance2 || (d2 == best.distance2 && s < best.s)) best = {d2, s, bary};
  };
  const Eigen::Vector3d n = (c[1] - c[0]).cross(c[2] - c[0]);
  if (!degenerate(c, n)) {
    const double da = n.dot(a - c[0]);
    const double db = n.dot(b - c[0]);
    if ((da <= 0.0 && db >= 0.0) || (da >= 0.0 && db <= 0.0)) {
      // The segment meets the plane; its crossing point is exact up to round-off, and
      // any error only raises the candidate (the boundary candidates bound the minimum).
      const double s = da != db ? std::clamp(da / (da - db), 0.0, 1.0) : 0.0;
      const Eigen::Vector3d q = a + s * (b - a);
      const TrianglePoint cp = closest_point_on_triangle(q, c);
      consider((cp.point - q).squaredNorm(), s, cp.barycentric);
    }
  }
  {
    const TrianglePoint cp = closest_point_on_triangle(a, c);
    consider((cp.point - a).squaredNorm(), 0.0, cp.barycentric);
  }
  {
    const TrianglePoint cp = closest_point_on_triangle(b, c);
    consider((cp.point - b).squaredNorm(), 1.0, cp.barycentric);
  }
  for (int e = 0; e < 3; ++e) {
    const int i = e;
    const int j = (e + 1) % 3;
    const SegmentSegmentClosest ss = closest_segment_segment(a, b, c[i], c[j]);
    Eigen::Vector3d bary = Eigen::Vector3d::Zero();
    bary[i] = 1.0 - ss.t;
    bary[j] = ss.t;
    consider(ss.distance2, ss.s, bary);
  }
  return best;
}

PreparedTriangle::PreparedTriangle(const TriangleCorners& c) : corners(c) {
  const Eigen::Vector3d n = (c[1] - c[0]).cross(c[2] - c[0]);
  degenerate = geometry::degenerate(c, n);
  if (!degenerate) unit_normal = n / n.norm();
}

bool segment_near_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const PreparedTriangle& t, double r) {
  if (t.slab_separates(a, b, r)) return false;
  if (!t.degenerate) {
    const double da = t.plane_distance(a);
    const double db = t.plane_distance(b);
    if ((da <= 0.0 && db >= 0.0) || (da >= 0.0 && db <= 0.0)) {
      // The segment meets the plane at q; q inside the triangle (all three edge
      // functions on the normal's side) means distance 0 <= r. Round-off can only
      // misplace q by ~1e-16 of the coordinates, far below r (see wedge_caster.hpp).
      const double s = da != db ? std::clamp(da / (da - db), 0.0, 1.0) : 0.0;
      const Eigen::Vector3d q = a + s * (b - a);
      const TriangleCorners& c = t.corners;
      const Eigen::Vector3d& n = t.unit_normal;
      if ((c[1] - c[0]).cross(q - c[0]).dot(n) >= 0.0 &&
          (c[2] - c[1]).cross(q - c[1]).dot(n) >= 0.0 &&
          (c[0] - c[2]).cross(q - c[2]).dot(n) >= 0.0) {
        return true;
      }
    }
  }
  return closest_segment_triangle(a, b, t.corners).distance2 <= r * r;
}

bool segment_near_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const TriangleCorners& c, double r) {
  return segment_near_triangle(a, b, PreparedTriangle(c), r);
}

}  // namespace shellflow::geometry
