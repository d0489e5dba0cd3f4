#include "shellflow/geometry/wedge_caster.hpp"

namespace shellflow::geometry {

WedgeCaster::WedgeCaster(std::vector<const TriangleBvh*> shells, double epsilon)
    : m_shells(std::move(shells)), m_epsilon(epsilon) {
  if (!(epsilon > 0.0)) throw Error("WedgeCaster: epsilon (wedge thickness) must be > 0");
  for (const TriangleBvh* shell : m_shells) {
    if (shell == nullptr) throw Error("WedgeCaster: null shell");
  }
}

bool WedgeCaster::inside(const Eigen::Vector3d& p, double epsilon) const {
  const double r = 0.5 * epsilon;
  const double r2 = r * r;
  const Aabb query(p.array() - r, p.array() + r);
  for (const TriangleBvh* shell : m_shells) {
    const std::span<const PreparedTriangle> prepared = shell->prepared_triangles();
    const bool found = shell->candidates_overlapping(query, [&](int t) {
      const PreparedTriangle& tri = prepared[t];
      if (tri.slab_separates(p, p, r)) return false;
      return point_triangle_distance2(p, tri.corners) <= r2;
    });
    if (found) return true;
  }
  return false;
}

bool WedgeCaster::blocked(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          double epsilon) const {
  const double r = 0.5 * epsilon;
  for (const TriangleBvh* shell : m_shells) {
    // The hierarchy's float lane test is a conservative superset of the exact box test,
    // and the exact wedge test decides (no false "visible" either way).
    const std::span<const PreparedTriangle> prepared = shell->prepared_triangles();
    const bool found = shell->candidates_near_segment(
        a, b, r, [&](int t) { return segment_near_triangle(a, b, prepared[t], r); });
    if (found) return true;
  }
  return false;
}

Visibility WedgeCaster::classify(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 double epsilon) const {
  // The segment contains B, so "B inside a wedge" implies "blocked": test the common
  // unblocked case with one traversal, and only then look for B inside a wedge.
  if (!blocked(a, b, epsilon)) return Visibility::Visible;
  return inside(b, epsilon) ? Visibility::Inside : Visibility::Occluded;
}

std::optional<WedgeHit> WedgeCaster::first_hit(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                               double epsilon) const {
  const double r = 0.5 * epsilon;
  const double r2 = r * r;
  std::optional<WedgeHit> best;
  for (int shell_index = 0; shell_index < static_cast<int>(m_shells.size()); ++shell_index) {
    const TriangleBvh& shell = *m_shells[shell_index];
    const std::span<const PreparedTriangle> prepared = shell.prepared_triangles();
    shell.candidates_near_segment(a, b, r, [&](int t) {
      const PreparedTriangle& tri = prepared[t];
      if (tri.slab_separates(a, b, r)) return false;
      const SegmentTriangleClosest c = closest_segment_triangle(a, b, tri.corners);
      if (c.distance2 <= r2 && (!best || c.s < best->s)) {
        best = WedgeHit{shell_index, t, c.s, c.barycentric};
      }
      return false;
    });
  }
  return best;
}

}  // namespace shellflow::geometry
