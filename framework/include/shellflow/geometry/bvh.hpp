#pragma once
// Bvh: a binary axis-aligned box hierarchy over a list of primitive boxes (§3: "a
// standard axis-aligned box hierarchy ... accelerating intersection tests"). It knows
// only boxes; TriangleBvh and SweptTriangleBvh put triangles in it.
//
// Layout: nodes in depth-first pre-order in one flat array; node 0 is the root, the
// left child of an inner node i is i + 1, its right child is `right`. A leaf holds
// `count` > 0 primitives m_order[first .. first + count). Built by median split of the
// primitive centres along the widest axis; refit() recomputes boxes bottom-up in O(n)
// without changing the tree, and the quality measure cost() = sum of inner-node box
// areas / root box area (the surface-area-heuristic cost, MacDonald–Booth 1990) tells
// when a refit tree has degraded enough to rebuild.

#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/aabb.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::geometry {

class Bvh {
 public:
  struct Node {
    Aabb box;
    int first_or_right = 0;  ///< leaf: first slot in m_order; inner: index of the right child
    int count = 0;           ///< leaf: number of primitives (> 0); inner: 0
  };

  /// Maximum primitives per leaf.
  static constexpr int kLeafSize = 4;
  /// Maximum traversal depth (a median-split tree of 2^40 primitives is shallower).
  static constexpr int kMaxDepth = 64;

  Bvh() = default;
  explicit Bvh(std::span<const Aabb> boxes) { build(boxes); }

  /// Builds the tree from scratch. O(n log n).
  void build(std::span<const Aabb> boxes);
  /// Recomputes all node boxes for moved primitives (same count, same order). O(n).
  void refit(std::span<const Aabb> boxes);
  /// Refits, then rebuilds if cost() grew past `max_degradation` times the cost right
  /// after the last build. Returns true when it rebuilt.
  bool refit_or_rebuild(std::span<const Aabb> boxes, double max_degradation);

  /// SAH quality: sum of inner-node areas over the root area (>= 0; lower is better).
  double cost() const { return m_cost; }
  /// cost() right after the last build().
  double build_cost() const { return m_build_cost; }
  int primitive_count() const { return static_cast<int>(m_order.size()); }
  int build_count() const { return m_build_count; }
  std::span<const Node> nodes() const { return m_nodes; }
  const Aabb& root_box() const { return m_nodes.front().box; }
  bool empty() const { return m_order.empty(); }

  /// Calls `visit(primitive)` for every primitive whose box passes `node_test(box)`
  /// (tested on nodes and then on the primitive's own box). `visit` returns true to stop
  /// the traversal early. Returns true when stopped early.
  template <class NodeTest, class Visit>
  bool traverse(std::span<const Aabb> boxes, NodeTest&& node_test, Visit&& visit) const {
    if (m_nodes.empty()) return false;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = m_nodes[stack[--top]];
      if (!node_test(node.box)) continue;
      if (node.count > 0) {
        for (int s = node.first_or_right; s < node.first_or_right + node.count; ++s) {
          const int primitive = m_order[s];
          if (node.count > 1 && !node_test(boxes[primitive])) continue;
          if (visit(primitive)) return true;
        }
      } else {
        const int self = static_cast<int>(&node - m_nodes.data());
        SHELLFLOW_ASSERT(top + 2 <= kMaxDepth);
        stack[top++] = node.first_or_right;
        stack[top++] = self + 1;
      }
    }
    return false;
  }

  /// Branch-and-bound nearest search: `distance2(primitive, best2)` returns the squared
  /// distance of the query to that primitive (it may return anything >= best2 when it can
  /// tell it is not closer); nodes farther than the best so far are skipped. Returns the
  /// best squared distance (infinity when empty) and the primitive in `best_primitive`.
  template <class NodeDistance2, class PrimitiveDistance2>
  double nearest(NodeDistance2&& node_distance2, PrimitiveDistance2&& distance2,
                 int& best_primitive) const {
    double best2 = std::numeric_limits<double>::infinity();
    best_primitive = -1;
    if (m_nodes.empty()) return best2;
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const int index = stack[--top];
      const Node& node = m_nodes[index];
      if (node_distance2(node.box) >= best2) continue;
      if (node.count > 0) {
        for (int s = node.first_or_right; s < node.first_or_right + node.count; ++s) {
          const double d2 = distance2(m_order[s], best2);
          if (d2 < best2) {
            best2 = d2;
            best_primitive = m_order[s];
          }
        }
      } else {
        // Visit the nearer child first so that the bound tightens quickly.
        const int left = index + 1;
        const int right = node.first_or_right;
        const bool left_first =
            node_distance2(m_nodes[left].box) <= node_distance2(m_nodes[right].box);
        SHELLFLOW_ASSERT(top + 2 <= kMaxDepth);
        stack[top++] = left_first ? right : left;
        stack[top++] = left_first ? left : right;
      }
    }
    return best2;
  }

 private:
  int build_recursive(std::span<const Aabb> boxes, std::span<const Eigen::Vector3d> centres,
                      int first, int count, int depth);
  double compute_cost() const;

  std::vector<Node> m_nodes;
  std::vector<int> m_order;
  double m_cost = 0.0;
  double m_build_cost = 0.0;
  int m_build_count = 0;
};

}  // namespace shellflow::geometry
