#pragma once
// Aabb: an axis-aligned box, the node type of the box hierarchy (§3: "a standard
// axis-aligned box hierarchy is used for the triangulated surface").

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <utility>

namespace shellflow::geometry {

struct Aabb {
  /// Default: the empty box (lower = +inf, upper = -inf), neutral for extend().
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  Aabb() = default;
  Aabb(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) : lower(lo), upper(hi) {}

  bool empty() const { return (upper.array() < lower.array()).any(); }
  void extend(const Eigen::Vector3d& p) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  void extend(const Aabb& b) {
    lower = lower.cwiseMin(b.lower);
    upper = upper.cwiseMax(b.upper);
  }
  /// Grows the box by `r` on every side.
  Aabb inflated(double r) const { return {lower.array() - r, upper.array() + r}; }
  Eigen::Vector3d center() const { return 0.5 * (lower + upper); }
  Eigen::Vector3d extent() const { return upper - lower; }
  /// Surface area; 0 for the empty box. Used as the refit quality measure (SAH cost).
  double surface_area() const {
    if (empty()) return 0.0;
    const Eigen::Vector3d e = extent();
    return 2.0 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
  }
  bool overlaps(const Aabb& b) const {
    return (lower.array() <= b.upper.array()).all() && (b.lower.array() <= upper.array()).all();
  }
  bool contains(const Eigen::Vector3d& p) const {
    return (lower.array() <= p.array()).all() && (p.array() <= upper.array()).all();
  }
  /// Squared distance from `p` to the box (0 inside).
  double squared_distance(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = (lower - p).cwiseMax(Eigen::Vector3d::Zero()).cwiseMax(p - upper);
    return d.squaredNorm();
  }

  /// Does the segment a + s (b - a), s in [0, 1], touch the box inflated by `r`?
  /// Slab test (Kay–Kajiya 1986) written without divisions by zero: an axis along
  /// which the segment does not move is tested as an interval containment. Conservative
  /// by construction: a box touched by the segment is never reported as missed.
  bool overlaps_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r) const {
    double s0 = 0.0;
    double s1 = 1.0;
    for (int k = 0; k < 3; ++k) {
      const double lo = lower[k] - r;
      const double hi = upper[k] + r;
      const double d = b[k] - a[k];
      if (d == 0.0) {
        if (a[k] < lo || a[k] > hi) return false;
        continue;
      }
      const double inv = 1.0 / d;
      double t0 = (lo - a[k]) * inv;
      double t1 = (hi - a[k]) * inv;
      if (t0 > t1) std::swap(t0, t1);
      s0 = t0 > s0 ? t0 : s0;
      s1 = t1 < s1 ? t1 : s1;
      if (s0 > s1) return false;
    }
    return true;
  }
};

/// Aabb::overlaps_segment with the per-segment work (inverse direction) done once, for
/// testing one segment against many boxes in a hierarchy traversal. Same answers.
class SegmentBoxQuery {
 public:
  SegmentBoxQuery(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r) : m_a(a), m_r(r) {
    for (int k = 0; k < 3; ++k) {
      const double d = b[k] - a[k];
      m_moving[k] = d != 0.0;
      m_inv[k] = m_moving[k] ? 1.0 / d : 0.0;
    }
  }
  bool operator()(const Aabb& box) const {
    double s0 = 0.0;
    double s1 = 1.0;
    for (int k = 0; k < 3; ++k) {
      const double lo = box.lower[k] - m_r;
      const double hi = box.upper[k] + m_r;
      if (!m_moving[k]) {
        if (m_a[k] < lo || m_a[k] > hi) return false;
        continue;
      }
      double t0 = (lo - m_a[k]) * m_inv[k];
      double t1 = (hi - m_a[k]) * m_inv[k];
      if (t0 > t1) std::swap(t0, t1);
      s0 = t0 > s0 ? t0 : s0;
      s1 = t1 < s1 ? t1 : s1;
      if (s0 > s1) return false;
    }
    return true;
  }

 private:
  Eigen::Vector3d m_a;
  Eigen::Vector3d m_inv;
  bool m_moving[3];
  double m_r;
};

}  // namespace shellflow::geometry
