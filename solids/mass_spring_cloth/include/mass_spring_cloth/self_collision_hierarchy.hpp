#pragma once
// Self-collision culling of one cloth by normal cones over a fixed patch hierarchy
// (Volino and Magnenat-Thalmann 1994, "Efficient self-collision detection on smoothly
// discretized surface animations using geometrical shape regularity", §3; the continuous
// normal cones of Tang, Curtis, Yoon, Manocha 2009, "ICCD: interactive continuous
// collision detection between deformable models using connectivity-based culling", §4).
//
// A patch that is a topological disc, whose triangle normals all lie within 90 degrees
// of one axis and whose boundary, projected along that axis, does not cross itself,
// projects one-to-one onto the plane normal to the axis (a degree argument: every point
// of the plane off the boundary is covered as many times as the boundary winds around
// it, at most once), so no two of its features that do not share a node can touch.
// The solver needs more: no such pair within the contact distance d (thickness plus the
// candidates' reuse margins). A patch is culled when, at every instant of the step,
//  - every normal is within 60 degrees of the axis (a cheap first rejection; 90 would
//    do for the proof),
//  - every triangle's projected heights exceed d (lower bound: axis . N over its
//    longest edge, N the unnormalised normal), and
//  - the projected boxes of boundary edges that share no node, each padded by d / 2,
//    do not overlap.
// Then two features that share no node are at least d apart in the projection, and 3D
// distances are at least the projected ones. In the projection (one-to-one) the point-
// triangle and edge-edge distances are those of a node to an edge without it; a
// straight path from the node leaves its first triangle through the opposite side, a
// height away, or leaves the patch at the node and re-enters through a boundary edge
// sharing no node with one of the node's two boundary edges. A flat or gently curved
// sheet whose triangles are not much thinner than d has no candidates beyond its pairs
// along folds.
// The instants are covered conservatively: each triangle's normal over a step with
// linear motion is a quadratic whose Bernstein coefficients (start, mid, end) bound it
// in their cone, and each boundary edge's projection over the step lies in the box of
// its four projected end points.
//
// The hierarchy is a binary tree over the triangles, one triangle per leaf, built once
// by median splits of the triangle centres at the positions it is given and refit
// (boxes, cones) every step, so its patches keep their topology: whether a node is a
// disc, and its boundary, are found once. Pairs of triangles come from descending the
// tree with pairs of nodes whose boxes overlap, skipping the self pairs of patches that
// pass the test above.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "shellflow/geometry/aabb.hpp"

namespace shellflow::cloth {

class SelfCollisionHierarchy {
 public:
  using Vectors = std::vector<Eigen::Vector3d>;

  /// Hierarchy over `triangles` (nodes index `positions`), shaped by those positions.
  void build(const std::vector<std::array<int, 3>>& triangles, const Vectors& positions);
  bool empty() const { return m_nodes.empty(); }
  int triangle_count() const { return static_cast<int>(m_triangles.size()); }
  const std::vector<std::array<int, 3>>& triangles() const { return m_triangles; }

  /// Per step: triangle boxes (indexed like the triangles of build()) and the motion
  /// a[k] -> b[k] of the nodes, for the normal cones and the boundary test.
  void update(const std::vector<geometry::Aabb>& triangle_boxes, const Vectors& a,
              const Vectors& b);
  /// Per step, when only for_each_overlap() will be asked: the boxes, without cones.
  void refit(const std::vector<geometry::Aabb>& triangle_boxes);

  /// Pairs (t1, t2), t1 != t2, of triangles whose boxes overlap, except pairs inside a
  /// patch none of whose features that share no node come within `distance` of each
  /// other during the motion a -> b given to update(). Each unordered pair comes once;
  /// order is unspecified. Returns how many patches were culled (the largest ones).
  int self_pairs(const Vectors& a, const Vectors& b, double distance,
                 std::vector<std::array<int, 2>>& out) const;

  /// Triangles whose boxes overlap `box`.
  template <class Visit>
  void for_each_overlap(const geometry::Aabb& box, Visit&& visit) const {
    if (m_nodes.empty()) return;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = m_nodes[stack[--top]];
      if (!node.box.overlaps(box)) continue;
      if (node.left < 0) {
        visit(m_order[node.first]);
      } else {
        stack[top++] = node.right;
        stack[top++] = node.left;
      }
    }
  }

 private:
  struct Node {
    geometry::Aabb box;
    int first = 0, count = 0;   ///< triangles m_order[first .. first + count)
    int left = -1, right = -1;  ///< children; -1 for a leaf (one triangle)
    /// The node's boundary edges m_boundary[boundary_first .. boundary_end) when the
    /// node is a disc; boundary_first = -1 when it is not (it is then never culled).
    int boundary_first = -1, boundary_end = -1;
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();  ///< cone axis (unnormalised)
  };
  static constexpr int kMaxDepth = 128;

  int build_recursive(std::vector<int>& order, const std::vector<Eigen::Vector3d>& centres,
                      int first, int count);
  /// Mesh adjacency for find_disc_boundary(): edges, the triangles at each edge (CSR)
  /// and per-node stamps, so each node's test is linear in its triangles.
  struct Adjacency;
  void find_disc_boundary(int index, Adjacency& adjacency);
  /// Do no two features of this node that share no mesh node come within `distance`
  /// during the motion a -> b?
  bool self_collision_free(const Node& node, const Vectors& a, const Vectors& b,
                           double distance) const;
  void collect_tasks(int x, int y, const Vectors& a, const Vectors& b, double distance,
                     std::vector<std::array<int, 2>>& tasks, int& culled) const;
  void self_recursive(int x, const Vectors& a, const Vectors& b, double distance,
                      std::vector<std::array<int, 2>>& out, int& culled) const;
  /// The pairs inside inner node x that is not self-collision-free: its children's own
  /// pairs and the pairs between them.
  void children_pairs(int x, const Vectors& a, const Vectors& b, double distance,
                      std::vector<std::array<int, 2>>& out, int& culled) const;
  void pair_recursive(int a, int b, std::vector<std::array<int, 2>>& out) const;

  std::vector<std::array<int, 3>> m_triangles;
  std::vector<Node> m_nodes;
  std::vector<int> m_order;
  std::vector<std::array<int, 2>> m_boundary;  ///< node pairs of boundary edges
  // Per step: unit normal generators per triangle (start, middle, end; the middle one
  // may be zero), their lengths over the triangle's longest edge over the step (lower
  // bounds of its heights, times the cosine to a projection axis) and whether the
  // triangle degenerates (zero normal at start or end).
  std::vector<std::array<Eigen::Vector3d, 3>> m_generators;
  std::vector<std::array<double, 3>> m_height_scales;
  std::vector<char> m_degenerate;
};

}  // namespace shellflow::cloth
