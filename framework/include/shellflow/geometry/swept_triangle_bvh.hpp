#pragma once
// SweptTriangleBvh: box hierarchy over the space each triangle occupies while its nodes
// move linearly from x^n to x^{n+1} (§3 swept-point invalidation). Each triangle's box
// is the union of its boxes at both ends, which contains the whole linear motion since
// every intermediate corner is a convex combination of its two end positions.

#include <vector>

#include "shellflow/geometry/bvh.hpp"
#include "shellflow/geometry/triangle_mesh.hpp"

namespace shellflow::geometry {

class SweptTriangleBvh {
 public:
  SweptTriangleBvh() = default;
  SweptTriangleBvh(const TriangleMesh& start, const TriangleMesh& end,
                   double max_degradation = 2.0);

  /// A new step (same topology): refit, rebuild if degraded. Returns true when rebuilt.
  bool update(const TriangleMesh& start, const TriangleMesh& end);

  const TriangleMesh& start() const { return m_start; }
  const TriangleMesh& end() const { return m_end; }
  const Bvh& bvh() const { return m_bvh; }
  std::span<const Aabb> boxes() const { return m_boxes; }

  /// Calls visit(triangle) for each triangle whose swept box overlaps `box`; visit
  /// returns true to stop. Returns true when stopped.
  template <class Visit>
  bool triangles_overlapping(const Aabb& box, Visit&& visit) const {
    return m_bvh.traverse(
        m_boxes, [&](const Aabb& node) { return node.overlaps(box); }, visit);
  }

 private:
  TriangleMesh m_start;
  TriangleMesh m_end;
  Bvh m_bvh;
  std::vector<Aabb> m_boxes;
  double m_max_degradation = 2.0;
};

}  // namespace shellflow::geometry
