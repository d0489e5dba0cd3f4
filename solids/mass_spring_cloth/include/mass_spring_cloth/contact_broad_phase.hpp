#pragma once
// Broad phase of cloth contact: which point–triangle and edge–edge pairs can come within
// a distance during a step. Each triangle gets the box of its corners' motion (start to
// end), inflated. The cloth's triangles sit in a fixed patch hierarchy
// (self_collision_hierarchy.hpp), refit every step, whose descent yields the cloth's own
// overlapping triangle pairs minus those inside patches whose features cannot come
// within the distance of each other (normal cones, projected heights and boundaries; a
// flat sheet yields none); other solids' triangles are queried against the same
// hierarchy. Each overlapping pair (t1, t2) yields the pairs of
// the vertices and edges the two triangles *own*: every vertex and edge is owned by
// exactly one of its triangles (the first), so each feature pair is produced once,
// without a global sort or hash (the feature assignment of Curtis, Tamstorf, Manocha
// 2008, "Fast collision detection for deformable models using representative-triangles").
// A feature's box lies inside each of its triangles' boxes, so every feature pair whose
// boxes overlap is found.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "mass_spring_cloth/self_collision_hierarchy.hpp"
#include "shellflow/geometry/aabb.hpp"

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
  /// if it has such a node. The hierarchy over the cloth's triangles is shaped by
  /// `rest_positions` (covering the cloth triangles' nodes), not by whatever shape the
  /// cloth has crumpled into, and is rebuilt only when those triangles change (not when
  /// other solids come or go).
  void set_topology(const std::vector<std::array<int, 3>>& triangles, int cloth_nodes,
                    bool self_collision, const Vectors& rest_positions);
  const std::vector<std::array<int, 2>>& edges() const { return m_edges; }

  /// Pairs whose features' boxes over the motion a[k] -> b[k] come within `distance`
  /// of each other (each box is inflated by distance / 2), except pairs inside a cloth
  /// patch in which no two features sharing no node come within `distance` at any
  /// instant of the motion. Order is unspecified.
  void find(const Vectors& a, const Vectors& b, double distance, ContactCandidates& out);
  /// Self-collision-free patches culled by the last find().
  int culled_patches() const { return m_culled_patches; }

 private:
  std::vector<std::array<int, 3>> m_triangles;
  std::vector<std::array<int, 2>> m_edges;
  int m_cloth_nodes = 0;
  bool m_self = true;
  // Features owned by each triangle, CSR by triangle.
  std::vector<int> m_node_start, m_owned_nodes, m_edge_start, m_owned_edges;

  std::vector<int> m_cloth_triangles;     ///< triangles with a cloth node, in hierarchy order
  std::vector<int> m_obstacle_triangles;  ///< the others
  SelfCollisionHierarchy m_hierarchy;
  int m_culled_patches = 0;
  std::vector<geometry::Aabb> m_node_boxes, m_edge_boxes, m_triangle_boxes, m_cloth_boxes;
  std::vector<std::array<int, 2>> m_triangle_pairs;
};

}  // namespace shellflow::cloth
