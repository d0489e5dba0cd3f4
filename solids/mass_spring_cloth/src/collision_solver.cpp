#include "mass_spring_cloth/collision_solver.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "mass_spring_cloth/contact_geometry.hpp"

namespace shellflow::cloth {

namespace {

using Box = Eigen::AlignedBox3d;

// Relative normal speed below which a continuous-collision pair counts as separating,
// as a fraction of thickness / h: a tiny push keeps the pair from staying coplanar.
constexpr double kCcdSeparationFraction = 1e-3;
// Distance at the coplanarity time below which a pair collides, as a fraction of the
// thickness (Bridson 2002 use a small tolerance on the coplanar distance).
constexpr double kCcdDistanceFraction = 1e-2;
// Proximity repulsion separates an overlap by this fraction per step (Bridson 2002 §7.2).
constexpr double kRepulsionFraction = 0.1;
constexpr int kMaxImpactZoneIterations = 100;
// Below this many primitives a loop runs serially: a parallel region costs more than it saves.
constexpr long kParallelThreshold = 4096;

int find_root(std::vector<int>& parent, int k) {
  while (parent[k] != k) {
    parent[k] = parent[parent[k]];
    k = parent[k];
  }
  return k;
}

}  // namespace

void CollisionSolver::set_topology(const std::vector<std::array<int, 3>>& triangles) {
  m_triangles = triangles;
  m_edges.clear();
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      m_edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(m_edges.begin(), m_edges.end());
  m_edges.erase(std::unique(m_edges.begin(), m_edges.end()), m_edges.end());
}

void CollisionSolver::set_parameters(double thickness, double friction, int ccd_passes) {
  m_thickness = thickness;
  m_friction = friction;
  m_ccd_passes = ccd_passes;
}

void CollisionSolver::find_candidates(const Vectors& a, const Vectors& b, double pad,
                                      Candidates& out) const {
  out.point_triangle.clear();
  out.edge_edge.clear();
  const int node_count = static_cast<int>(a.size());
  const auto node_box = [&](int k) {
    Box box(a[k]);
    box.extend(b[k]);
    return box;
  };

  std::vector<Box> triangle_boxes(m_triangles.size());
#pragma omp parallel for schedule(static) if (m_triangles.size() > kParallelThreshold)
  for (int t = 0; t < static_cast<int>(m_triangles.size()); ++t) {
    Box box = node_box(m_triangles[t][0]);
    box.extend(node_box(m_triangles[t][1]));
    box.extend(node_box(m_triangles[t][2]));
    triangle_boxes[t] = Box(box.min().array() - pad, box.max().array() + pad);
  }
  std::vector<Box> edge_boxes(m_edges.size());
#pragma omp parallel for schedule(static) if (m_edges.size() > kParallelThreshold)
  for (int e = 0; e < static_cast<int>(m_edges.size()); ++e) {
    Box box = node_box(m_edges[e][0]);
    box.extend(node_box(m_edges[e][1]));
    edge_boxes[e] = Box(box.min().array() - pad, box.max().array() + pad);
  }

  SpatialHash triangle_hash, edge_hash;
  triangle_hash.build(triangle_boxes, m_cell_size);
  edge_hash.build(edge_boxes, m_cell_size);

#pragma omp parallel if (m_edges.size() > kParallelThreshold)
  {
    std::vector<int> found;
    std::vector<std::array<int, 2>> pt, ee;
#pragma omp for schedule(dynamic, 256) nowait
    for (int k = 0; k < node_count; ++k) {
      triangle_hash.query(node_box(k), found);
      for (int t : found) {
        const auto& tri = m_triangles[t];
        if (tri[0] == k || tri[1] == k || tri[2] == k) continue;
        if (!m_self && k < m_cloth_nodes && tri[0] < m_cloth_nodes) continue;
        pt.push_back({k, t});
      }
    }
#pragma omp for schedule(dynamic, 256) nowait
    for (int e = 0; e < static_cast<int>(m_edges.size()); ++e) {
      edge_hash.query(edge_boxes[e], found);
      const auto& ea = m_edges[e];
      for (int f : found) {
        if (f <= e) continue;
        const auto& eb = m_edges[f];
        if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
        if (!m_self && ea[0] < m_cloth_nodes && eb[0] < m_cloth_nodes) continue;
        ee.push_back({e, f});
      }
    }
#pragma omp critical
    {
      out.point_triangle.insert(out.point_triangle.end(), pt.begin(), pt.end());
      out.edge_edge.insert(out.edge_edge.end(), ee.begin(), ee.end());
    }
  }
  // Thread order must not change the result: contacts are applied in pair order.
  std::sort(out.point_triangle.begin(), out.point_triangle.end());
  std::sort(out.edge_edge.begin(), out.edge_edge.end());
}

void CollisionSolver::proximity_contacts(const Vectors& x0, const Vectors& v,
                                         const std::vector<double>& inverse_mass, double h,
                                         const Candidates& pairs, std::vector<Contact>& out) const {
  out.clear();
  const double thickness = m_thickness;
  for (const auto& [k, t] : pairs.point_triangle) {
    const auto& tri = m_triangles[t];
    if (inverse_mass[k] == 0.0 && inverse_mass[tri[0]] == 0.0 && inverse_mass[tri[1]] == 0.0 &&
        inverse_mass[tri[2]] == 0.0)
      continue;
    const Eigen::Vector3d w = closest_point_triangle(x0[k], x0[tri[0]], x0[tri[1]], x0[tri[2]]);
    const Eigen::Vector3d q = w[0] * x0[tri[0]] + w[1] * x0[tri[1]] + w[2] * x0[tri[2]];
    const Eigen::Vector3d d = x0[k] - q;
    const double dist = d.norm();
    if (dist >= thickness) continue;
    Eigen::Vector3d n;
    if (dist > 1e-9 * thickness) {
      n = d / dist;
    } else {  // on the triangle: push against the approach direction
      n = (x0[tri[1]] - x0[tri[0]]).cross(x0[tri[2]] - x0[tri[0]]).normalized();
      const Eigen::Vector3d vr = v[k] - (w[0] * v[tri[0]] + w[1] * v[tri[1]] + w[2] * v[tri[2]]);
      if (vr.dot(n) > 0.0) n = -n;
    }
    out.push_back({{k, tri[0], tri[1], tri[2]},
                   {1.0, -w[0], -w[1], -w[2]},
                   n,
                   kRepulsionFraction * (thickness - dist) / h});
  }
  for (const auto& [e, f] : pairs.edge_edge) {
    const auto& ea = m_edges[e];
    const auto& eb = m_edges[f];
    if (inverse_mass[ea[0]] == 0.0 && inverse_mass[ea[1]] == 0.0 && inverse_mass[eb[0]] == 0.0 &&
        inverse_mass[eb[1]] == 0.0)
      continue;
    const Eigen::Vector2d st = closest_points_segments(x0[ea[0]], x0[ea[1]], x0[eb[0]], x0[eb[1]]);
    const double s = st[0], u = st[1];
    const Eigen::Vector3d d =
        ((1 - s) * x0[ea[0]] + s * x0[ea[1]]) - ((1 - u) * x0[eb[0]] + u * x0[eb[1]]);
    const double dist = d.norm();
    if (dist >= thickness || dist <= 1e-9 * thickness) continue;
    // Point–triangle pairs cover the end points; edge pairs only count in their interiors.
    if (s <= 0.0 || s >= 1.0 || u <= 0.0 || u >= 1.0) continue;
    out.push_back({{ea[0], ea[1], eb[0], eb[1]},
                   {1 - s, s, -(1 - u), -u},
                   d / dist,
                   kRepulsionFraction * (thickness - dist) / h});
  }
}

void CollisionSolver::ccd_contacts(const Vectors& x0, const Vectors& v,
                                   const std::vector<double>& inverse_mass, double h,
                                   const Candidates& pairs, const std::vector<char>* active,
                                   std::vector<Contact>& out) const {
  out.clear();
  std::vector<std::pair<long, Contact>> keyed;  // (pair order, contact)
  const double eps = kCcdDistanceFraction * m_thickness;
  const double target = kCcdSeparationFraction * m_thickness / h;
  const auto is_active = [&](const std::array<int, 4>& nodes) {
    if (!active) return true;
    for (int k : nodes)
      if ((*active)[k]) return true;
    return false;
  };
  const auto all_fixed = [&](const std::array<int, 4>& nodes) {
    for (int k : nodes)
      if (inverse_mass[k] != 0.0) return false;
    return true;
  };

#pragma omp parallel if (pairs.point_triangle.size() + pairs.edge_edge.size() > kParallelThreshold)
  {
    std::vector<std::pair<long, Contact>> local;
#pragma omp for schedule(dynamic, 1024) nowait
    for (long p = 0; p < static_cast<long>(pairs.point_triangle.size()); ++p) {
      const auto [k, t] = pairs.point_triangle[p];
      const auto& tri = m_triangles[t];
      const std::array<int, 4> nodes{k, tri[0], tri[1], tri[2]};
      if (all_fixed(nodes) || !is_active(nodes)) continue;
      std::array<Eigen::Vector3d, 4> x, d;
      for (int i = 0; i < 4; ++i) {
        x[i] = x0[nodes[i]];
        d[i] = h * v[nodes[i]];
      }
      std::array<double, 3> times;
      const int count = coplanarity_times(x, d, times);
      for (int r = 0; r < count; ++r) {
        std::array<Eigen::Vector3d, 4> y;
        for (int i = 0; i < 4; ++i) y[i] = x[i] + times[r] * d[i];
        const Eigen::Vector3d w = closest_point_triangle(y[0], y[1], y[2], y[3]);
        const Eigen::Vector3d q = w[0] * y[1] + w[1] * y[2] + w[2] * y[3];
        if ((y[0] - q).norm() >= eps) continue;
        Eigen::Vector3d n = (y[2] - y[1]).cross(y[3] - y[1]);
        if (n.norm() == 0.0) continue;
        n.normalize();
        const double side = (x[0] - (w[0] * x[1] + w[1] * x[2] + w[2] * x[3])).dot(n);
        if (side < 0.0) n = -n;
        local.push_back({p, Contact{nodes, {1.0, -w[0], -w[1], -w[2]}, n, target}});
        break;
      }
    }
    const long offset = static_cast<long>(pairs.point_triangle.size());
#pragma omp for schedule(dynamic, 1024) nowait
    for (long p = 0; p < static_cast<long>(pairs.edge_edge.size()); ++p) {
      const auto [e, f] = pairs.edge_edge[p];
      const std::array<int, 4> nodes{m_edges[e][0], m_edges[e][1], m_edges[f][0], m_edges[f][1]};
      if (all_fixed(nodes) || !is_active(nodes)) continue;
      std::array<Eigen::Vector3d, 4> x, d;
      for (int i = 0; i < 4; ++i) {
        x[i] = x0[nodes[i]];
        d[i] = h * v[nodes[i]];
      }
      std::array<double, 3> times;
      const int count = coplanarity_times(x, d, times);
      for (int r = 0; r < count; ++r) {
        std::array<Eigen::Vector3d, 4> y;
        for (int i = 0; i < 4; ++i) y[i] = x[i] + times[r] * d[i];
        const Eigen::Vector2d st = closest_points_segments(y[0], y[1], y[2], y[3]);
        const double s = st[0], u = st[1];
        const Eigen::Vector3d pa = (1 - s) * y[0] + s * y[1], pb = (1 - u) * y[2] + u * y[3];
        if ((pa - pb).norm() >= eps) continue;
        Eigen::Vector3d n = (y[1] - y[0]).cross(y[3] - y[2]);
        if (n.norm() <= 1e-12 * (y[1] - y[0]).norm() * (y[3] - y[2]).norm()) n = pa - pb;
        if (n.norm() == 0.0) continue;
        n.normalize();
        const double side = (((1 - s) * x[0] + s * x[1]) - ((1 - u) * x[2] + u * x[3])).dot(n);
        if (side < 0.0) n = -n;
        local.push_back({offset + p, Contact{nodes, {1 - s, s, -(1 - u), -u}, n, target}});
        break;
      }
    }
#pragma omp critical
    keyed.insert(keyed.end(), local.begin(), local.end());
  }
  // Thread order must not change the result: contacts are applied in pair order.
  std::sort(keyed.begin(), keyed.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& item : keyed) out.push_back(item.second);
}

void CollisionSolver::apply(const Contact& c, Vectors& v, const std::vector<double>& inverse_mass,
                            double friction) const {
  Eigen::Vector3d vr = Eigen::Vector3d::Zero();
  double denom = 0.0;
  for (int i = 0; i < 4; ++i) {
    vr += c.weights[i] * v[c.nodes[i]];
    denom += c.weights[i] * c.weights[i] * inverse_mass[c.nodes[i]];
  }
  const double vn = vr.dot(c.normal);
  if (vn >= c.target_speed || denom <= 0.0) return;
  const double dvn = c.target_speed - vn;
  Eigen::Vector3d dv = dvn * c.normal;  // change of the relative velocity
  if (friction > 0.0) {  // Coulomb friction on the relative tangential velocity (§7.3)
    const Eigen::Vector3d vt = vr - vn * c.normal;
    const double vt_norm = vt.norm();
    if (vt_norm > 0.0) dv -= std::min(1.0, friction * dvn / vt_norm) * vt;
  }
  const Eigen::Vector3d impulse = dv / denom;
  for (int i = 0; i < 4; ++i) v[c.nodes[i]] += c.weights[i] * inverse_mass[c.nodes[i]] * impulse;
}

CollisionStatistics CollisionSolver::resolve(const Vectors& x0, Vectors& v,
                                             const std::vector<double>& inverse_mass, double h) {
  CollisionStatistics stats;
  const int n = static_cast<int>(x0.size());
  if (m_triangles.empty()) return stats;
  double mean_edge = 0.0;
  for (const auto& e : m_edges) mean_edge += (x0[e[0]] - x0[e[1]]).norm();
  mean_edge /= static_cast<double>(m_edges.size());
  m_cell_size = std::max(mean_edge, 2.0 * m_thickness);

  // 1. Proximity at the start of the step.
  Candidates near;
  find_candidates(x0, x0, m_thickness, near);
  std::vector<Contact> contacts;
  proximity_contacts(x0, v, inverse_mass, h, near, contacts);
  for (const auto& c : contacts) apply(c, v, inverse_mass, m_friction);
  stats.proximity_contacts = static_cast<int>(contacts.size());

  // 2. Continuous collision passes over the swept candidates.
  Vectors x1(n);
  for (int k = 0; k < n; ++k) x1[k] = x0[k] + h * v[k];
  Candidates swept;
  find_candidates(x0, x1, m_thickness, swept);
  std::vector<char> active(n, 1);
  bool colliding = false;
  for (int pass = 0; pass < m_ccd_passes; ++pass) {
    ccd_contacts(x0, v, inverse_mass, h, swept, pass == 0 ? nullptr : &active, contacts);
    stats.ccd_collisions += static_cast<int>(contacts.size());
    colliding = !contacts.empty();
    if (!colliding) break;
    std::fill(active.begin(), active.end(), 0);
    for (const auto& c : contacts) {
      apply(c, v, inverse_mass, 0.0);
      for (int k : c.nodes) active[k] = 1;
    }
  }
  if (!colliding) return stats;

  // 3. Rigid impact zones (translations) until no pair collides.
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int iteration = 0; iteration < kMaxImpactZoneIterations; ++iteration) {
    for (int k = 0; k < n; ++k) x1[k] = x0[k] + h * v[k];
    find_candidates(x0, x1, m_thickness, swept);
    ccd_contacts(x0, v, inverse_mass, h, swept, nullptr, contacts);
    if (contacts.empty()) break;
    stats.ccd_collisions += static_cast<int>(contacts.size());
    for (const auto& c : contacts)
      for (int i = 1; i < 4; ++i) {
        const int a = find_root(parent, c.nodes[0]), b = find_root(parent, c.nodes[i]);
        if (a != b) parent[b] = a;
      }
    // Zone velocity: mass-weighted mean, or the mean of its fixed nodes if it has any.
    std::vector<Eigen::Vector3d> momentum(n, Eigen::Vector3d::Zero()),
        fixed_sum(n, Eigen::Vector3d::Zero());
    std::vector<double> mass(n, 0.0), fixed_count(n, 0.0), size(n, 0.0);
    for (int k = 0; k < n; ++k) {
      const int r = find_root(parent, k);
      size[r] += 1.0;
      if (inverse_mass[k] == 0.0) {
        fixed_sum[r] += v[k];
        fixed_count[r] += 1.0;
      } else {
        momentum[r] += v[k] / inverse_mass[k];
        mass[r] += 1.0 / inverse_mass[k];
      }
    }
    stats.impact_zones = 0;
    for (int k = 0; k < n; ++k)
      if (find_root(parent, k) == k && size[k] > 1.0) ++stats.impact_zones;
    for (int k = 0; k < n; ++k) {
      const int r = find_root(parent, k);
      if (size[r] <= 1.0 || inverse_mass[k] == 0.0) continue;
      v[k] = fixed_count[r] > 0.0 ? Eigen::Vector3d(fixed_sum[r] / fixed_count[r])
                                  : Eigen::Vector3d(momentum[r] / mass[r]);
    }
  }
  return stats;
}

}  // namespace shellflow::cloth
