#include "shellflow/geometry/triangle_mesh.hpp"

namespace shellflow::geometry {

void TriangleMesh::boxes(std::vector<Aabb>& out) const {
  const int n = triangle_count();
  out.resize(n);
#pragma omp parallel for schedule(static) if (n > 20000)
  for (int t = 0; t < n; ++t) out[t] = box(t);
}

void TriangleMesh::swept_boxes(const TriangleMesh& end, std::vector<Aabb>& out) const {
  const int n = triangle_count();
  out.resize(n);
#pragma omp parallel for schedule(static) if (n > 20000)
  for (int t = 0; t < n; ++t) {
    Aabb b = box(t);
    b.extend(end.box(t));
    out[t] = b;
  }
}

Aabb TriangleMesh::bounds() const {
  Aabb b;
  for (int i = 0; i < node_count(); ++i) b.extend(node(i));
  return b;
}

}  // namespace shellflow::geometry
