#include "mass_spring_cloth/self_collision_hierarchy.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "shellflow/geometry/mesh_edges.hpp"

namespace shellflow::cloth {

namespace {

// A patch passes the cone test when every normal is within 60 degrees of its axis. The
// no-crossing argument needs only 90 degrees, and the proximity proof needs only the
// projected heights (see the header); the narrower cone is kept as a cheap first
// rejection, which measured no cull lost in the benchmarks (the hanging 30K-triangle
// curtain is still one culled patch).
constexpr double kMinCosine = 0.5;
// Boundary boxes in the projection are padded, beyond half the contact distance, by
// this fraction of the coordinates' magnitude, so round-off cannot separate boundary
// edges that touch.
constexpr double kRelativePad = 1e-9;
// Node pairs with up to this many triangles together are one parallel task.
constexpr int kTaskTriangles = 512;
// Below this many triangles the per-step loops run serially.
constexpr int kParallelThreshold = 2048;

}  // namespace

struct SelfCollisionHierarchy::Adjacency : geometry::MeshEdges {
  Adjacency(const std::vector<std::array<int, 3>>& triangles, int node_count)
      : geometry::MeshEdges(triangles) {
    const int n = static_cast<int>(triangles.size());
    triangle_stamp.assign(n, -1);
    visited_stamp.assign(n, -1);
    edge_stamp.assign(edges.size(), -1);
    vertex_stamp.assign(node_count, -1);
    vertex_boundary.assign(node_count, 0);
  }
  // Stamped with the node under test, so nothing is cleared between nodes.
  std::vector<int> triangle_stamp, visited_stamp, edge_stamp, vertex_stamp;
  std::vector<int> vertex_boundary;  ///< boundary edges at a node, valid where stamped
};

void SelfCollisionHierarchy::build(const std::vector<std::array<int, 3>>& triangles,
                                   const Vectors& positions) {
  m_triangles = triangles;
  m_nodes.clear();
  m_boundary.clear();
  const int n = static_cast<int>(triangles.size());
  m_order.resize(n);
  std::iota(m_order.begin(), m_order.end(), 0);
  if (n == 0) return;
  std::vector<Eigen::Vector3d> centres(n);
  for (int t = 0; t < n; ++t)
    centres[t] =
        (positions[triangles[t][0]] + positions[triangles[t][1]] + positions[triangles[t][2]]) /
        3.0;
  m_nodes.reserve(2 * static_cast<size_t>(n));
  build_recursive(m_order, centres, 0, n);
  Adjacency adjacency(triangles, static_cast<int>(positions.size()));
  for (int i = 0; i < static_cast<int>(m_nodes.size()); ++i)
    if (m_nodes[i].count > 1) find_disc_boundary(i, adjacency);
}

int SelfCollisionHierarchy::build_recursive(std::vector<int>& order,
                                            const std::vector<Eigen::Vector3d>& centres, int first,
                                            int count) {
  const int index = static_cast<int>(m_nodes.size());
  m_nodes.emplace_back();
  m_nodes[index].first = first;
  m_nodes[index].count = count;
  if (count == 1) return index;
  // Median split along the widest extent of the centres (ties broken by index, so the
  // tree does not depend on the standard library's partition).
  geometry::Aabb bounds;
  for (int i = first; i < first + count; ++i) bounds.extend(centres[order[i]]);
  int axis = 0;
  bounds.extent().maxCoeff(&axis);
  const int middle = first + count / 2;
  std::nth_element(order.begin() + first, order.begin() + middle, order.begin() + first + count,
                   [&](int s, int t) {
                     return centres[s][axis] < centres[t][axis] ||
                            (centres[s][axis] == centres[t][axis] && s < t);
                   });
  const int left = build_recursive(order, centres, first, middle - first);
  const int right = build_recursive(order, centres, middle, first + count - middle);
  m_nodes[index].left = left;
  m_nodes[index].right = right;
  return index;
}

void SelfCollisionHierarchy::find_disc_boundary(int index, Adjacency& adj) {
  Node& node = m_nodes[index];
  for (int i = node.first; i < node.first + node.count; ++i) adj.triangle_stamp[m_order[i]] = index;
  // Disc: every edge in one or two of the node's triangles, every mesh node on the
  // boundary in exactly two boundary edges (no pinched nodes), edge-connected, and
  // Euler characteristic V - E + F = 1.
  long vertex_count = 0, edge_count = 0;
  std::vector<std::array<int, 2>> boundary;
  for (int i = node.first; i < node.first + node.count; ++i) {
    const int t = m_order[i];
    for (int k = 0; k < 3; ++k) {
      const int v = m_triangles[t][k];
      if (adj.vertex_stamp[v] != index) {
        adj.vertex_stamp[v] = index;
        adj.vertex_boundary[v] = 0;
        ++vertex_count;
      }
      const int e = adj.triangle_edges[t][k];
      if (adj.edge_stamp[e] == index) continue;
      adj.edge_stamp[e] = index;
      ++edge_count;
      int inside = 0;
      for (int p = adj.edge_start[e]; p < adj.edge_start[e + 1]; ++p)
        inside += adj.triangle_stamp[adj.edge_triangles[p]] == index;
      if (inside > 2) return;
      if (inside == 1) boundary.push_back(adj.edges[e]);
    }
  }
  if (vertex_count - edge_count + node.count != 1) return;
  for (const auto& [p, q] : boundary) ++adj.vertex_boundary[p], ++adj.vertex_boundary[q];
  for (const auto& [p, q] : boundary)
    if (adj.vertex_boundary[p] != 2 || adj.vertex_boundary[q] != 2) return;
  // Edge-connected: a search over shared edges reaches every triangle.
  std::vector<int> stack{m_order[node.first]};
  adj.visited_stamp[stack.back()] = index;
  int reached = 0;
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    ++reached;
    for (int e : adj.triangle_edges[t])
      for (int p = adj.edge_start[e]; p < adj.edge_start[e + 1]; ++p) {
        const int u = adj.edge_triangles[p];
        if (adj.triangle_stamp[u] == index && adj.visited_stamp[u] != index) {
          adj.visited_stamp[u] = index;
          stack.push_back(u);
        }
      }
  }
  if (reached != node.count) return;
  node.boundary_first = static_cast<int>(m_boundary.size());
  m_boundary.insert(m_boundary.end(), boundary.begin(), boundary.end());
  node.boundary_end = static_cast<int>(m_boundary.size());
}

void SelfCollisionHierarchy::update(const std::vector<geometry::Aabb>& triangle_boxes,
                                    const Vectors& a, const Vectors& b) {
  const int n = static_cast<int>(m_triangles.size());
  m_generators.resize(n);
  m_height_scales.resize(n);
  m_degenerate.resize(n);
#pragma omp parallel for schedule(static) if (n > kParallelThreshold)
  for (int t = 0; t < n; ++t) {
    const auto& tri = m_triangles[t];
    const Eigen::Vector3d e1a = a[tri[1]] - a[tri[0]], e2a = a[tri[2]] - a[tri[0]];
    const Eigen::Vector3d e1b = b[tri[1]] - b[tri[0]], e2b = b[tri[2]] - b[tri[0]];
    // n(t) = (1-t)^2 n_start + 2t(1-t) n_middle + t^2 n_end (Tang et al. 2009, §4.1).
    const std::array<Eigen::Vector3d, 3> normals{
        e1a.cross(e2a), 0.5 * (e1a.cross(e2b) + e1b.cross(e2a)), e1b.cross(e2b)};
    // Edges move linearly, so each one's length over the step is at most the larger of
    // its lengths at the start and the end (convexity of the norm).
    const Eigen::Vector3d e3a = a[tri[2]] - a[tri[1]], e3b = b[tri[2]] - b[tri[1]];
    const double longest_edge =
        std::sqrt(std::max({e1a.squaredNorm(), e2a.squaredNorm(), e3a.squaredNorm(),
                            e1b.squaredNorm(), e2b.squaredNorm(), e3b.squaredNorm()}));
    auto& g = m_generators[t];
    for (int k = 0; k < 3; ++k) {
      const double norm = normals[k].norm();
      g[k] = norm > 0.0 ? Eigen::Vector3d(normals[k] / norm) : Eigen::Vector3d::Zero();
      m_height_scales[t][k] = longest_edge > 0.0 ? norm / longest_edge : 0.0;
    }
    m_degenerate[t] = g[0].isZero(0.0) || g[2].isZero(0.0);
  }
  refit(triangle_boxes);
  // Cone axes bottom-up: children come after their parent in m_nodes.
  for (int i = static_cast<int>(m_nodes.size()) - 1; i >= 0; --i) {
    Node& node = m_nodes[i];
    node.normal_sum = node.left < 0 ? Eigen::Vector3d(m_generators[m_order[node.first]][0] +
                                                      m_generators[m_order[node.first]][2])
                                    : Eigen::Vector3d(m_nodes[node.left].normal_sum +
                                                      m_nodes[node.right].normal_sum);
  }
}

void SelfCollisionHierarchy::refit(const std::vector<geometry::Aabb>& triangle_boxes) {
  for (int i = static_cast<int>(m_nodes.size()) - 1; i >= 0; --i) {
    Node& node = m_nodes[i];
    if (node.left < 0) {
      node.box = triangle_boxes[m_order[node.first]];
    } else {
      node.box = m_nodes[node.left].box;
      node.box.extend(m_nodes[node.right].box);
    }
  }
}

bool SelfCollisionHierarchy::self_collision_free(const Node& node, const Vectors& a,
                                                 const Vectors& b, double distance) const {
  if (node.count == 1) return true;  // a triangle's features all share its nodes
  if (node.boundary_first < 0) return false;
  const double axis_norm = node.normal_sum.norm();
  if (!(axis_norm > 0.0)) return false;
  const Eigen::Vector3d axis = node.normal_sum / axis_norm;
  // Cone: every normal generator of every triangle within 60 degrees of the axis, and
  // every triangle's projected heights over the step above `distance`: a height is
  // twice the projected area over a projected edge, at least axis . N(t) over the
  // longest edge, and axis . N(t) is at least its smallest Bernstein coefficient.
  for (int i = node.first; i < node.first + node.count; ++i) {
    const int t = m_order[i];
    if (m_degenerate[t]) return false;
    for (int k = 0; k < 3; ++k) {
      const double cosine = axis.dot(m_generators[t][k]);
      if (!(cosine > kMinCosine) || !(cosine * m_height_scales[t][k] > distance)) return false;
    }
  }
  // Boundary: projected along the axis, boundary edges that share no node must stay
  // `distance` apart over the whole step; each edge's sweep lies in the box of its four
  // corners, padded by half the distance.
  Eigen::Vector3d u = axis.unitOrthogonal();
  const Eigen::Vector3d w = axis.cross(u);
  struct Box2 {
    double x0, x1, y0, y1;
    int p, q;
  };
  std::vector<Box2> boxes;
  boxes.reserve(node.boundary_end - node.boundary_first);
  double magnitude = 0.0;
  for (int e = node.boundary_first; e < node.boundary_end; ++e) {
    const auto [p, q] = m_boundary[e];
    Box2 box{INFINITY, -INFINITY, INFINITY, -INFINITY, p, q};
    for (const Eigen::Vector3d* x : {&a[p], &a[q], &b[p], &b[q]}) {
      const double s = u.dot(*x), r = w.dot(*x);
      box.x0 = std::min(box.x0, s), box.x1 = std::max(box.x1, s);
      box.y0 = std::min(box.y0, r), box.y1 = std::max(box.y1, r);
      magnitude = std::max(magnitude, x->cwiseAbs().maxCoeff());
    }
    boxes.push_back(box);
  }
  const double pad = distance + 2.0 * kRelativePad * magnitude;  // both boxes' pads
  std::sort(boxes.begin(), boxes.end(), [](const Box2& s, const Box2& t) { return s.x0 < t.x0; });
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size() && boxes[j].x0 <= boxes[i].x1 + pad; ++j) {
      const Box2 &s = boxes[i], &t = boxes[j];
      if (s.p == t.p || s.p == t.q || s.q == t.p || s.q == t.q) continue;
      if (s.y0 <= t.y1 + pad && t.y0 <= s.y1 + pad) return false;
    }
  return true;
}

void SelfCollisionHierarchy::collect_tasks(int x, int y, const Vectors& a, const Vectors& b,
                                           double distance, std::vector<std::array<int, 2>>& tasks,
                                           int& culled) const {
  const Node &nx = m_nodes[x], &ny = m_nodes[y];
  if (x == y) {
    if (nx.left < 0) return;
    if (self_collision_free(nx, a, b, distance)) {
      ++culled;
      return;
    }
    if (nx.count <= kTaskTriangles) {
      tasks.push_back({x, x});
      return;
    }
    collect_tasks(nx.left, nx.left, a, b, distance, tasks, culled);
    collect_tasks(nx.right, nx.right, a, b, distance, tasks, culled);
    collect_tasks(nx.left, nx.right, a, b, distance, tasks, culled);
    return;
  }
  if (!nx.box.overlaps(ny.box)) return;
  if (nx.count + ny.count <= kTaskTriangles || (nx.left < 0 && ny.left < 0)) {
    tasks.push_back({x, y});
    return;
  }
  if (ny.left < 0 || (nx.left >= 0 && nx.count >= ny.count)) {
    collect_tasks(nx.left, y, a, b, distance, tasks, culled);
    collect_tasks(nx.right, y, a, b, distance, tasks, culled);
  } else {
    collect_tasks(x, ny.left, a, b, distance, tasks, culled);
    collect_tasks(x, ny.right, a, b, distance, tasks, culled);
  }
}

void SelfCollisionHierarchy::self_recursive(int x, const Vectors& a, const Vectors& b,
                                            double distance, std::vector<std::array<int, 2>>& out,
                                            int& culled) const {
  const Node& node = m_nodes[x];
  if (node.left < 0) return;
  if (self_collision_free(node, a, b, distance)) {
    ++culled;
    return;
  }
  children_pairs(x, a, b, distance, out, culled);
}

void SelfCollisionHierarchy::children_pairs(int x, const Vectors& a, const Vectors& b,
                                            double distance, std::vector<std::array<int, 2>>& out,
                                            int& culled) const {
  const Node& node = m_nodes[x];
  self_recursive(node.left, a, b, distance, out, culled);
  self_recursive(node.right, a, b, distance, out, culled);
  pair_recursive(node.left, node.right, out);
}

void SelfCollisionHierarchy::pair_recursive(int x, int y,
                                            std::vector<std::array<int, 2>>& out) const {
  const Node &nx = m_nodes[x], &ny = m_nodes[y];
  if (!nx.box.overlaps(ny.box)) return;
  if (nx.left < 0 && ny.left < 0) {
    out.push_back({m_order[nx.first], m_order[ny.first]});
  } else if (ny.left < 0 || (nx.left >= 0 && nx.count >= ny.count)) {
    pair_recursive(nx.left, y, out);
    pair_recursive(nx.right, y, out);
  } else {
    pair_recursive(x, ny.left, out);
    pair_recursive(x, ny.right, out);
  }
}

int SelfCollisionHierarchy::self_pairs(const Vectors& a, const Vectors& b, double distance,
                                       std::vector<std::array<int, 2>>& out) const {
  out.clear();
  if (m_nodes.empty()) return 0;
  std::vector<std::array<int, 2>> tasks;
  int culled = 0;
  collect_tasks(0, 0, a, b, distance, tasks, culled);
  const int task_count = static_cast<int>(tasks.size());
#pragma omp parallel if (task_count > 1 && triangle_count() > kParallelThreshold) reduction(+ : culled)
  {
    std::vector<std::array<int, 2>> local;
#pragma omp for schedule(dynamic, 1) nowait
    for (int i = 0; i < task_count; ++i) {
      if (tasks[i][0] == tasks[i][1])  // collect_tasks found it not self-collision-free
        children_pairs(tasks[i][0], a, b, distance, local, culled);
      else
        pair_recursive(tasks[i][0], tasks[i][1], local);
    }
#pragma omp critical
    out.insert(out.end(), local.begin(), local.end());
  }
  return culled;
}

}  // namespace shellflow::cloth
