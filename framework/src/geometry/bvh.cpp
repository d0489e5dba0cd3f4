#include "shellflow/geometry/bvh.hpp"

#include <algorithm>
#include <numeric>

namespace shellflow::geometry {

void Bvh::build(std::span<const Aabb> boxes) {
  const int n = static_cast<int>(boxes.size());
  m_nodes.clear();
  m_order.resize(n);
  std::iota(m_order.begin(), m_order.end(), 0);
  ++m_build_count;
  if (n == 0) {
    m_cost = m_build_cost = 0.0;
    return;
  }
  std::vector<Eigen::Vector3d> centres(n);
  for (int i = 0; i < n; ++i) centres[i] = boxes[i].center();
  m_nodes.reserve(2 * (n / kLeafSize + 1));
  build_recursive(boxes, centres, 0, n, 0);
  m_cost = m_build_cost = compute_cost();
}

int Bvh::build_recursive(std::span<const Aabb> boxes, std::span<const Eigen::Vector3d> centres,
                         int first, int count, int depth) {
  const int index = static_cast<int>(m_nodes.size());
  m_nodes.emplace_back();
  Aabb box;
  Aabb centre_box;
  for (int s = first; s < first + count; ++s) {
    box.extend(boxes[m_order[s]]);
    centre_box.extend(centres[m_order[s]]);
  }
  m_nodes[index].box = box;
  // Depth guard: a median split halves the count, so depth stays ~log2(n) < kMaxDepth - 2.
  if (count <= kLeafSize || depth >= kMaxDepth - 2) {
    m_nodes[index].first_or_right = first;
    m_nodes[index].count = count;
    return index;
  }
  int axis = 0;
  centre_box.extent().maxCoeff(&axis);
  const int half = count / 2;
  auto begin = m_order.begin() + first;
  std::nth_element(begin, begin + half, begin + count,
                   [&](int a, int b) { return centres[a][axis] < centres[b][axis]; });
  build_recursive(boxes, centres, first, half, depth + 1);
  const int right = build_recursive(boxes, centres, first + half, count - half, depth + 1);
  m_nodes[index].first_or_right = right;
  m_nodes[index].count = 0;
  return index;
}

void Bvh::refit(std::span<const Aabb> boxes) {
  if (static_cast<int>(boxes.size()) != primitive_count()) {
    throw Error("Bvh::refit: primitive count changed; call build() instead");
  }
  // Children have larger indices than their parent (pre-order), so a reverse sweep
  // sees both children before the parent.
  for (int i = static_cast<int>(m_nodes.size()) - 1; i >= 0; --i) {
    Node& node = m_nodes[i];
    Aabb box;
    if (node.count > 0) {
      for (int s = node.first_or_right; s < node.first_or_right + node.count; ++s) {
        box.extend(boxes[m_order[s]]);
      }
    } else {
      box = m_nodes[i + 1].box;
      box.extend(m_nodes[node.first_or_right].box);
    }
    node.box = box;
  }
  m_cost = compute_cost();
}

bool Bvh::refit_or_rebuild(std::span<const Aabb> boxes, double max_degradation) {
  if (m_nodes.empty() || static_cast<int>(boxes.size()) != primitive_count()) {
    build(boxes);
    return true;
  }
  refit(boxes);
  if (m_cost > max_degradation * m_build_cost) {
    build(boxes);
    return true;
  }
  return false;
}

double Bvh::compute_cost() const {
  const double root_area = m_nodes.front().box.surface_area();
  if (!(root_area > 0.0)) return 0.0;
  double sum = 0.0;
  for (const Node& node : m_nodes) {
    if (node.count == 0) sum += node.box.surface_area();
  }
  return sum / root_area;
}

}  // namespace shellflow::geometry
