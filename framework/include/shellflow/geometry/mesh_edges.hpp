#pragma once
// MeshEdges: the edges of a triangle mesh, each once, sorted by their (low, high) nodes,
// with the triangles at each edge in increasing order (so the first is the edge's owner
// in the cloth's contact feature assignment) and the three edges of each triangle. Shared
// by the cloth's contact broad phase and self-collision hierarchy, and kinematic_shell's
// edge strain.

#include <array>
#include <vector>

#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::geometry {

struct MeshEdges {
  explicit MeshEdges(const std::vector<std::array<int, 3>>& triangles);
  explicit MeshEdges(const sdk::Triangles& triangles);

  /// Edge e lies on the mesh's open boundary: one triangle has it (a rim, a hem).
  bool open(int e) const { return edge_start[e + 1] - edge_start[e] == 1; }

  std::vector<std::array<int, 2>> edges;           ///< (low node, high node)
  std::vector<std::array<int, 3>> triangle_edges;  ///< edge k of t joins corners k, k + 1
  std::vector<int> edge_start, edge_triangles;     ///< CSR: triangles at each edge
};

}  // namespace shellflow::geometry
