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
//
// Compact layout for the hot queries (segment casts, §3 wedge visibility): the same tree
// collapsed to 4 children per node (Wald, Benthin, Boulos 2008, "Getting rid of packets";
// Dammertz et al. 2008), each node holding its children's boxes as float rows (one
// cache-friendly 128-byte node, the 4 boxes tested together), and the primitives of the
// binary leaves pulled up into the lanes so that a leaf-level box test is a lane too.
// Float boxes are rounded outward, and WideSegmentQuery pads them by a slack larger
// than its float round-off, so the compact test never misses a box the exact double
// test (Aabb::overlaps_segment) would touch: it may only report a few more.

#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

  /// A node of the compact 4-wide layout: lane j is a child box, rounded outward to
  /// float; child[j] >= 0 is another WideNode, child[j] < 0 is primitive ~child[j].
  /// Lanes [0, lanes) are used.
  struct alignas(64) WideNode {
    float lower[3][4];
    float upper[3][4];
    int child[4];
    int lanes = 0;
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
  /// The compact 4-wide layout of the same tree (node 0 is the root).
  std::span<const WideNode> wide_nodes() const { return m_wide; }
  /// Largest |coordinate| of the root box: the scale of the float round-off in wide_nodes().
  double coordinate_scale() const { return m_scale; }

  /// Calls `visit(primitive)` for every primitive whose lane passes `lanes(node)` (a
  /// bit mask, bit j for lane j, tested on every node on the way down); `visit` returns
  /// true to stop. Primitive lanes are visited before the node's inner lanes are
  /// descended, so an any-hit query stops early. Returns true when stopped early.
  template <class LaneTest, class Visit>
  bool traverse_wide(LaneTest&& lanes, Visit&& visit) const {
    if (m_wide.empty()) return false;
    int stack[kWideStack];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const WideNode& node = m_wide[stack[--top]];
      unsigned mask = lanes(node);
      while (mask != 0) {
        const int j = std::countr_zero(mask);
        mask &= mask - 1;
        const int child = node.child[j];
        if (child < 0) {
          if (visit(~child)) return true;
        } else {
          SHELLFLOW_ASSERT(top < kWideStack);
          stack[top++] = child;
        }
      }
    }
    return false;
  }

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
  int build_wide(int binary);
  void refit_wide(std::span<const Aabb> boxes);
  void set_lane(int wide, int lane, const Aabb& box);

  /// Wide traversal stack: each level pops one node and pushes at most 4.
  static constexpr int kWideStack = 3 * kMaxDepth + 4;

  std::vector<Node> m_nodes;
  std::vector<int> m_order;
  std::vector<WideNode> m_wide;
  /// Per wide lane, what its box is taken from on refit: >= 0 a binary node, < 0 ~primitive.
  std::vector<int> m_wide_source;
  double m_scale = 0.0;
  double m_cost = 0.0;
  double m_build_cost = 0.0;
  int m_build_count = 0;
};

/// Segment [a, b] against the 4 lanes of a Bvh::WideNode, each box inflated by r: the
/// slab test of SegmentBoxQuery in float, 4 lanes at once. Conservative: the boxes are
/// padded by a slack of 2^-18 times the coordinate magnitude (the tree's scale plus the
/// segment's), far above the float round-off of the test (a few 2^-24 of that magnitude:
/// rounding the origin, the inverse direction, one subtraction and one product), so every
/// lane whose exact box the segment touches passes. Axes along which the segment moves
/// less than half the slack are tested as fixed (interval containment).
class WideSegmentQuery {
 public:
  WideSegmentQuery(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r, double scale);
  unsigned operator()(const Bvh::WideNode& node) const {
#if defined(__SSE2__)
    // The 4 lanes in one SSE register (x86-64 always has SSE2).
    __m128 s0 = _mm_setzero_ps();
    __m128 s1 = _mm_set1_ps(1.0f);
    __m128 ok = _mm_castsi128_ps(_mm_set1_epi32(-1));
    for (int k = 0; k < 3; ++k) {
      const __m128 lower = _mm_load_ps(node.lower[k]);
      const __m128 upper = _mm_load_ps(node.upper[k]);
      if (m_fixed[k]) {
        // Inside the inflated slab: lower - pad <= a <= upper + pad.
        ok = _mm_and_ps(ok, _mm_cmple_ps(lower, _mm_set1_ps(m_near[k])));
        ok = _mm_and_ps(ok, _mm_cmpge_ps(upper, _mm_set1_ps(m_far[k])));
        continue;
      }
      const __m128 near = m_positive[k] ? lower : upper;
      const __m128 far = m_positive[k] ? upper : lower;
      const __m128 inv = _mm_set1_ps(m_inv[k]);
      s0 = _mm_max_ps(s0, _mm_mul_ps(_mm_sub_ps(near, _mm_set1_ps(m_near[k])), inv));
      s1 = _mm_min_ps(s1, _mm_mul_ps(_mm_sub_ps(far, _mm_set1_ps(m_far[k])), inv));
    }
    const unsigned mask =
        static_cast<unsigned>(_mm_movemask_ps(_mm_and_ps(ok, _mm_cmple_ps(s0, s1))));
#else
    float s0[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    float s1[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    for (int k = 0; k < 3; ++k) {
      if (m_fixed[k]) {
        for (int j = 0; j < 4; ++j) {
          const bool in = node.lower[k][j] <= m_near[k] && node.upper[k][j] >= m_far[k];
          s0[j] = in ? s0[j] : 2.0f;
        }
        continue;
      }
      const float* near = m_positive[k] ? node.lower[k] : node.upper[k];
      const float* far = m_positive[k] ? node.upper[k] : node.lower[k];
      for (int j = 0; j < 4; ++j) {
        const float tn = (near[j] - m_near[k]) * m_inv[k];
        const float tf = (far[j] - m_far[k]) * m_inv[k];
        s0[j] = tn > s0[j] ? tn : s0[j];
        s1[j] = tf < s1[j] ? tf : s1[j];
      }
    }
    unsigned mask = 0;
    for (int j = 0; j < 4; ++j) mask |= static_cast<unsigned>(s0[j] <= s1[j]) << j;
#endif
    return mask & ((1u << node.lanes) - 1u);
  }

  /// The relative slack (see the class comment).
  static constexpr double kRelativeSlack = 0x1p-18;

 private:
  /// Moving axes: the origins of the near and far planes' parameters (a ± pad, the sign
  /// chosen by the direction); fixed axes: a + pad and a - pad.
  float m_near[3];
  float m_far[3];
  float m_inv[3];
  bool m_fixed[3];
  bool m_positive[3];
};

/// A box against the 4 lanes of a Bvh::WideNode: the overlap test in float, with the
/// query box rounded outward, so every lane whose exact box overlaps it passes.
class WideBoxQuery {
 public:
  explicit WideBoxQuery(const Aabb& box);
  unsigned operator()(const Bvh::WideNode& node) const {
#if defined(__SSE2__)
    __m128 ok = _mm_castsi128_ps(_mm_set1_epi32(-1));
    for (int k = 0; k < 3; ++k) {
      ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_load_ps(node.lower[k]), _mm_set1_ps(m_upper[k])));
      ok = _mm_and_ps(ok, _mm_cmpge_ps(_mm_load_ps(node.upper[k]), _mm_set1_ps(m_lower[k])));
    }
    const unsigned mask = static_cast<unsigned>(_mm_movemask_ps(ok));
#else
    unsigned mask = 0;
    for (int j = 0; j < 4; ++j) {
      bool in = true;
      for (int k = 0; k < 3; ++k) {
        in = in && node.lower[k][j] <= m_upper[k] && node.upper[k][j] >= m_lower[k];
      }
      mask |= static_cast<unsigned>(in) << j;
    }
#endif
    return mask & ((1u << node.lanes) - 1u);
  }

 private:
  float m_lower[3];
  float m_upper[3];
};

}  // namespace shellflow::geometry
