#include "shellflow/geometry/mesh_edges.hpp"

#include <algorithm>

namespace shellflow::geometry {

namespace {
std::vector<std::array<int, 3>> corner_list(const sdk::Triangles& triangles) {
  std::vector<std::array<int, 3>> corners(static_cast<size_t>(triangles.rows()));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    corners[static_cast<size_t>(t)] = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
  return corners;
}
}  // namespace

MeshEdges::MeshEdges(const sdk::Triangles& triangles) : MeshEdges(corner_list(triangles)) {}

MeshEdges::MeshEdges(const std::vector<std::array<int, 3>>& triangles) {
  const int n = static_cast<int>(triangles.size());
  std::vector<std::array<int, 4>> ends;  // (low node, high node, triangle, corner)
  ends.reserve(3 * static_cast<size_t>(n));
  for (int t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int p = triangles[t][k], q = triangles[t][(k + 1) % 3];
      ends.push_back({std::min(p, q), std::max(p, q), t, k});
    }
  std::sort(ends.begin(), ends.end());
  triangle_edges.resize(n);
  edge_start.push_back(0);
  for (size_t e = 0; e < ends.size(); ++e) {
    if (e > 0 && (ends[e][0] != ends[e - 1][0] || ends[e][1] != ends[e - 1][1])) {
      edges.push_back({ends[e - 1][0], ends[e - 1][1]});
      edge_start.push_back(static_cast<int>(edge_triangles.size()));
    }
    triangle_edges[ends[e][2]][ends[e][3]] = static_cast<int>(edges.size());
    edge_triangles.push_back(ends[e][2]);
  }
  if (!ends.empty()) {
    edges.push_back({ends.back()[0], ends.back()[1]});
    edge_start.push_back(static_cast<int>(edge_triangles.size()));
  }
}

}  // namespace shellflow::geometry
