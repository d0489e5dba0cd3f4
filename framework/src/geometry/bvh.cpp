#include "shellflow/geometry/bvh.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace shellflow::geometry {

namespace {

/// The largest float <= x (x rounded toward -infinity).
float round_down(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity())
                                    : f;
}
/// The smallest float >= x (x rounded toward +infinity).
float round_up(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

double scale_of(const Aabb& box) {
  return std::max(box.lower.cwiseAbs().maxCoeff(), box.upper.cwiseAbs().maxCoeff());
}

}  // namespace

void Bvh::build(std::span<const Aabb> boxes) {
  const int n = static_cast<int>(boxes.size());
  m_nodes.clear();
  m_wide.clear();
  m_wide_source.clear();
  m_scale = 0.0;
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
  m_wide.reserve(m_nodes.size() / 2 + 1);
  m_wide_source.reserve(4 * (m_nodes.size() / 2 + 1));
  build_wide(0);
  refit_wide(boxes);
  m_cost = m_build_cost = compute_cost();
}

int Bvh::build_wide(int binary) {
  // The lanes of the new node: binary nodes (>= 0) or single primitives (~primitive).
  // Start from the binary node's children (or its primitives if it is a leaf), then
  // greedily open the largest lane while its children still fit in 4 lanes.
  int items[4];
  int count = 0;
  const auto open = [&](int node, int* out) {
    const Node& n = m_nodes[node];
    int k = 0;
    if (n.count > 0) {
      for (int s = n.first_or_right; s < n.first_or_right + n.count; ++s) out[k++] = ~m_order[s];
    } else {
      out[k++] = node + 1;
      out[k++] = n.first_or_right;
    }
    return k;
  };
  const auto single = [&](int item) {
    // A binary leaf with one primitive is that primitive.
    if (item >= 0 && m_nodes[item].count == 1) return ~m_order[m_nodes[item].first_or_right];
    return item;
  };
  count = open(binary, items);
  for (int i = 0; i < count; ++i) items[i] = single(items[i]);
  while (true) {
    int best = -1;
    double best_area = -1.0;
    for (int i = 0; i < count; ++i) {
      if (items[i] < 0) continue;
      const Node& n = m_nodes[items[i]];
      const int opened = n.count > 0 ? n.count : 2;
      if (count - 1 + opened > 4) continue;
      const double area = n.box.surface_area();
      if (area > best_area) {
        best_area = area;
        best = i;
      }
    }
    if (best < 0) break;
    int children[4];
    const int opened = open(items[best], children);
    items[best] = single(children[0]);
    for (int k = 1; k < opened; ++k) items[count++] = single(children[k]);
  }
  const int index = static_cast<int>(m_wide.size());
  m_wide.emplace_back();
  m_wide_source.resize(m_wide_source.size() + 4, 0);
  m_wide[index].lanes = count;
  for (int j = 0; j < 4; ++j) {
    set_lane(index, j, Aabb());
    m_wide[index].child[j] = 0;
  }
  for (int j = 0; j < count; ++j) {
    m_wide_source[4 * index + j] = items[j];
    // Every binary item left here has more than one primitive: it gets its own node.
    const int child = items[j] < 0 ? items[j] : build_wide(items[j]);
    m_wide[index].child[j] = child;
  }
  return index;
}

void Bvh::set_lane(int wide, int lane, const Aabb& box) {
  WideNode& node = m_wide[wide];
  for (int k = 0; k < 3; ++k) {
    node.lower[k][lane] = round_down(box.lower[k]);
    node.upper[k][lane] = round_up(box.upper[k]);
  }
}

void Bvh::refit_wide(std::span<const Aabb> boxes) {
  for (int w = 0; w < static_cast<int>(m_wide.size()); ++w) {
    for (int j = 0; j < m_wide[w].lanes; ++j) {
      const int source = m_wide_source[4 * w + j];
      set_lane(w, j, source >= 0 ? m_nodes[source].box : boxes[~source]);
    }
  }
  m_scale = m_nodes.empty() ? 0.0 : scale_of(m_nodes.front().box);
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
  refit_wide(boxes);
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

WideSegmentQuery::WideSegmentQuery(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                                   double scale) {
  const double magnitude = scale + a.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff() + r;
  // The absolute floor keeps 1/d finite in float for a degenerate all-zero scene.
  const double slack = std::max(kRelativeSlack * magnitude, 1e-30);
  const double pad = r + slack;
  for (int k = 0; k < 3; ++k) {
    const double d = b[k] - a[k];
    m_fixed[k] = !(std::abs(d) > 0.5 * slack);
    m_positive[k] = d >= 0.0;
    m_inv[k] = m_fixed[k] ? 0.0f : static_cast<float>(1.0 / d);
    // Rounded to nearest: an error of 2^-24 of the magnitude, inside the slack.
    const float plus = static_cast<float>(a[k] + pad);
    const float minus = static_cast<float>(a[k] - pad);
    m_near[k] = m_fixed[k] || m_positive[k] ? plus : minus;
    m_far[k] = m_fixed[k] || m_positive[k] ? minus : plus;
  }
}

WideBoxQuery::WideBoxQuery(const Aabb& box) {
  for (int k = 0; k < 3; ++k) {
    m_lower[k] = round_down(box.lower[k]);
    m_upper[k] = round_up(box.upper[k]);
  }
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
