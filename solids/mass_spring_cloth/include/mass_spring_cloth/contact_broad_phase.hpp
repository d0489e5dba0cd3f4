#pragma once
// Broad phase of cloth contact: which point–triangle and edge–edge pairs can come within
// a distance during a step. Each triangle gets the box of its corners' motion (start to
// end), inflated; the boxes go into the framework's box hierarchy (geometry::Bvh), which
// is refit every step and rebuilt only when the refit tree has degraded. Overlapping
// triangle pairs are found by one box query per triangle, and each overlapping pair
// (t1, t2) yields the pairs of the vertices and edges the two triangles *own*: every
// vertex and edge is owned by exactly one of its triangles (the first), so each feature
// pair is produced once, without a global sort or hash (the feature assignment of
// Curtis, Tamstorf, Manocha 2008, "Fast collision detection for deformable models using
// representative-triangles"). A feature's box lies inside each of its triangles' boxes,
// so every feature pair whose boxes overlap is found.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "shellflow/geometry/aabb.hpp"
#include "shellflow/geometry/bvh.hpp"

namespace shellflow::cloth {

struct ContactCandidates {
  std::vector<std::array<int, 2>> point_triangle;  ///< (node, triangle)
  std::vector<std::array<int, 2>> edge_edge;       ///< (edge, edge), first < second
};

class ContactBroadPhase {
 public:
  using Vectors = std::vector<Eigen::Vector3d>;

  /// Triangles over nodes [0, n). Nodes >= `cloth_nodes` belong to other solids: pairs
  /// with only such nodes never count, and without `self_collision` a pair counts only
  /// if it has such a node.
  void set_topology(const std::vector<std::array<int, 3>>& triangles, int cloth_nodes,
                    bool self_collision);
  const std::vector<std::array<int, 2>>& edges() const { return m_edges; }

  /// Pairs whose features' boxes over the motion a[k] -> b[k] come within `distance`
  /// of each other (each box is inflated by distance / 2). Order is unspecified.
  void find(const Vectors& a, const Vectors& b, double distance, ContactCandidates& out);

 private:
  std::vector<std::array<int, 3>> m_triangles;
  std::vector<std::array<int, 2>> m_edges;
  std::vector<char> m_obstacle_triangle;  ///< all three nodes belong to another solid
  int m_cloth_nodes = 0;
  bool m_self = true;
  // Features owned by each triangle, CSR by triangle.
  std::vector<int> m_node_start, m_owned_nodes, m_edge_start, m_owned_edges;

  geometry::Bvh m_bvh;
  std::vector<geometry::Aabb> m_node_boxes, m_edge_boxes, m_triangle_boxes;
};

}  // namespace shellflow::cloth
