#include "mass_spring_cloth/collision_solver.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "shellflow/geometry/cubic_roots.hpp"
#include "shellflow/geometry/swept_point.hpp"
#include "shellflow/geometry/triangle_distance.hpp"

namespace shellflow::cloth {

namespace {

// Relative normal speed below which a continuous-collision pair counts as separating,
// as a fraction of thickness / h: a tiny push keeps the pair from staying coplanar.
constexpr double kCcdSeparationFraction = 1e-3;
// Distance at the coplanarity time below which a pair collides, as a fraction of the
// thickness (Bridson 2002 use a small tolerance on the coplanar distance).
constexpr double kCcdDistanceFraction = 1e-2;
// Proximity repulsion separates an overlap by this fraction per step (Bridson 2002 §7.2).
constexpr double kRepulsionFraction = 0.1;
constexpr int kMaxImpactZoneIterations = 100;
// Candidates are found for the motion padded by this many thicknesses, and reused while
// no node's end position has moved farther than that (Euclidean: the self-collision
// culling proves distances, not per-coordinate gaps, so a pair it culls at thickness +
// 2 margins stays beyond the thickness).
constexpr double kCandidateMarginThicknesses = 0.25;
// Below this many pairs a loop runs serially: a parallel region costs more than it saves.
constexpr long kParallelThreshold = 4096;

int find_root(std::vector<int>& parent, int k) {
  while (parent[k] != k) {
    parent[k] = parent[parent[k]];
    k = parent[k];
  }
  return k;
}

// Bernstein sign test: a cubic on [0, 1] lies in the convex hull of its Bernstein
// coefficients, so if all of them exceed `tolerance` in magnitude with one sign, the
// cubic has no root and no near-root there.
bool cubic_stays_away_from_zero(const std::array<double, 4>& c, double tolerance) {
  const double b0 = c[0], b1 = c[0] + c[1] / 3.0, b2 = c[0] + (2.0 * c[1] + c[2]) / 3.0,
               b3 = c[0] + c[1] + c[2] + c[3];
  return (b0 > tolerance && b1 > tolerance && b2 > tolerance && b3 > tolerance) ||
         (b0 < -tolerance && b1 < -tolerance && b2 < -tolerance && b3 < -tolerance);
}

// Times in [0, 1] at which x[k] + t d[k], k = 0..3, are coplanar up to `distance` times
// the scale `area2` (twice the triangle area, or |e1 x e2|): the cubic
// det[x1 - x0, x2 - x0, x3 - x0](t) through the framework's coplanarity_cubic (in the
// frame moving with x0) and cubic_near_roots.
geometry::NearRoots coplanarity_times(const std::array<Eigen::Vector3d, 4>& x,
                                      const std::array<Eigen::Vector3d, 4>& d, double tolerance) {
  const geometry::TriangleCorners start{x[1], x[2], x[3]};
  const geometry::TriangleCorners end{x[1] + d[1] - d[0], x[2] + d[2] - d[0], x[3] + d[3] - d[0]};
  const auto cubic = geometry::coplanarity_cubic(x[0], start, end);
  if (cubic_stays_away_from_zero(cubic, tolerance)) return {};
  return geometry::cubic_near_roots(cubic, tolerance);
}

}  // namespace

void CollisionSolver::set_topology(const std::vector<std::array<int, 3>>& triangles,
                                   int cloth_nodes, bool self_collision,
                                   const Vectors& rest_positions) {
  m_triangles = triangles;
  m_broad_phase.set_topology(triangles, cloth_nodes, self_collision, rest_positions);
  m_candidates_valid = false;
}

void CollisionSolver::set_parameters(double thickness, double friction, int ccd_passes) {
  m_thickness = thickness;
  m_friction = friction;
  m_ccd_passes = ccd_passes;
}

void CollisionSolver::update_candidates(const Vectors& x0, const Vectors& v, double h,
                                        CollisionStatistics& stats) {
  const int n = static_cast<int>(x0.size());
  const double margin = kCandidateMarginThicknesses * m_thickness;
  if (m_candidates_valid && static_cast<int>(m_candidate_motion.size()) == n) {
    double stray = 0.0;
#pragma omp parallel for schedule(static) reduction(max : stray) if (n > kParallelThreshold)
    for (int k = 0; k < n; ++k) stray = std::max(stray, (h * v[k] - m_candidate_motion[k]).norm());
    if (stray <= margin) return;
  }
  m_candidate_motion.resize(n);
  Vectors x1(n);
  for (int k = 0; k < n; ++k) {
    m_candidate_motion[k] = h * v[k];
    x1[k] = x0[k] + m_candidate_motion[k];
  }
  // Boxes inflated by (thickness + 2 margin) / 2 each: pairs within the thickness stay
  // candidates while each node stays within the margin of its end position.
  m_broad_phase.find(x0, x1, m_thickness + 2.0 * margin, m_candidates);
  m_candidates_valid = true;
  m_pt_distance.assign(m_candidates.point_triangle.size(), 0.0);
  m_ee_distance.assign(m_candidates.edge_edge.size(), 0.0);
  ++stats.broad_phases;
  stats.candidate_pairs =
      static_cast<int>(m_candidates.point_triangle.size() + m_candidates.edge_edge.size());
  stats.culled_patches = m_broad_phase.culled_patches();
}

void CollisionSolver::proximity_contacts(const Vectors& x0, const Vectors& v,
                                         const std::vector<double>& inverse_mass, double h,
                                         std::vector<Contact>& out) {
  const double thickness = m_thickness;
  const auto& edges = m_broad_phase.edges();
  const auto& pt_pairs = m_candidates.point_triangle;
  const auto& ee_pairs = m_candidates.edge_edge;
  std::vector<Keyed> keyed;
#pragma omp parallel if (pt_pairs.size() + ee_pairs.size() > kParallelThreshold)
  {
    std::vector<Keyed> local;
#pragma omp for schedule(dynamic, 1024) nowait
    for (long p = 0; p < static_cast<long>(pt_pairs.size()); ++p) {
      const auto [k, t] = pt_pairs[p];
      const auto& tri = m_triangles[t];
      if (inverse_mass[k] == 0.0 && inverse_mass[tri[0]] == 0.0 && inverse_mass[tri[1]] == 0.0 &&
          inverse_mass[tri[2]] == 0.0)
        continue;
      const geometry::TriangleCorners corners{x0[tri[0]], x0[tri[1]], x0[tri[2]]};
      // Cheap rejection: the triangle's box at the start, inflated, misses the point.
      const geometry::Aabb box(
          corners[0].cwiseMin(corners[1]).cwiseMin(corners[2]).array() - thickness,
          corners[0].cwiseMax(corners[1]).cwiseMax(corners[2]).array() + thickness);
      if (!box.contains(x0[k])) {
        m_pt_distance[p] = thickness;  // outside the inflated box: farther than that
        continue;
      }
      const auto closest = geometry::closest_point_on_triangle(x0[k], corners);
      const Eigen::Vector3d d = x0[k] - closest.point;
      const double dist = d.norm();
      m_pt_distance[p] = dist;
      if (dist >= thickness) continue;
      const Eigen::Vector3d& w = closest.barycentric;
      Eigen::Vector3d n;
      if (dist > 1e-9 * thickness) {
        n = d / dist;
      } else {  // on the triangle: push against the approach direction
        n = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalized();
        const Eigen::Vector3d vr = v[k] - (w[0] * v[tri[0]] + w[1] * v[tri[1]] + w[2] * v[tri[2]]);
        if (vr.dot(n) > 0.0) n = -n;
      }
      local.push_back({{0, k, t},
                       Contact{{k, tri[0], tri[1], tri[2]},
                               {1.0, -w[0], -w[1], -w[2]},
                               n,
                               kRepulsionFraction * (thickness - dist) / h}});
    }
#pragma omp for schedule(dynamic, 1024) nowait
    for (long p = 0; p < static_cast<long>(ee_pairs.size()); ++p) {
      const auto [e, f] = ee_pairs[p];
      const auto& ea = edges[e];
      const auto& eb = edges[f];
      if (inverse_mass[ea[0]] == 0.0 && inverse_mass[ea[1]] == 0.0 && inverse_mass[eb[0]] == 0.0 &&
          inverse_mass[eb[1]] == 0.0)
        continue;
      // Cheap rejection: the edges' boxes at the start, inflated, do not overlap.
      const geometry::Aabb box_a(x0[ea[0]].cwiseMin(x0[ea[1]]).array() - thickness,
                                 x0[ea[0]].cwiseMax(x0[ea[1]]).array() + thickness);
      const geometry::Aabb box_b(x0[eb[0]].cwiseMin(x0[eb[1]]), x0[eb[0]].cwiseMax(x0[eb[1]]));
      if (!box_a.overlaps(box_b)) {
        m_ee_distance[p] = thickness;
        continue;
      }
      const auto closest =
          geometry::closest_segment_segment(x0[ea[0]], x0[ea[1]], x0[eb[0]], x0[eb[1]]);
      m_ee_distance[p] = std::sqrt(closest.distance2);
      const double s = closest.s, u = closest.t;
      // Point–triangle pairs cover the end points; edge pairs only count in their interiors.
      if (s <= 0.0 || s >= 1.0 || u <= 0.0 || u >= 1.0) continue;
      const double dist = std::sqrt(closest.distance2);
      if (dist >= thickness || dist <= 1e-9 * thickness) continue;
      const Eigen::Vector3d d =
          ((1 - s) * x0[ea[0]] + s * x0[ea[1]]) - ((1 - u) * x0[eb[0]] + u * x0[eb[1]]);
      local.push_back({{1, e, f},
                       Contact{{ea[0], ea[1], eb[0], eb[1]},
                               {1 - s, s, -(1 - u), -u},
                               d / d.norm(),
                               kRepulsionFraction * (thickness - dist) / h}});
    }
#pragma omp critical
    keyed.insert(keyed.end(), local.begin(), local.end());
  }
  // Thread order must not change the result: contacts are applied in pair order.
  std::sort(keyed.begin(), keyed.end(),
            [](const Keyed& a, const Keyed& b) { return a.first < b.first; });
  out.clear();
  for (auto& item : keyed) out.push_back(item.second);
}

void CollisionSolver::ccd_contacts(const Vectors& x0, const Vectors& v,
                                   const std::vector<double>& inverse_mass, double h,
                                   const std::vector<char>* active,
                                   std::vector<Contact>& out) const {
  const auto& edges = m_broad_phase.edges();
  const auto& pt_pairs = m_candidates.point_triangle;
  const auto& ee_pairs = m_candidates.edge_edge;
  std::vector<Keyed> keyed;
  const double eps = kCcdDistanceFraction * m_thickness;
  const double target = kCcdSeparationFraction * m_thickness / h;
  const auto skip = [&](const std::array<int, 4>& nodes) {
    bool movable = false, is_active = active == nullptr;
    for (int k : nodes) {
      movable = movable || inverse_mass[k] != 0.0;
      is_active = is_active || (*active)[k];
    }
    return !movable || !is_active;
  };
  const auto motion = [&](const std::array<int, 4>& nodes, std::array<Eigen::Vector3d, 4>& x,
                          std::array<Eigen::Vector3d, 4>& d) {
    for (int i = 0; i < 4; ++i) {
      x[i] = x0[nodes[i]];
      d[i] = h * v[nodes[i]];
    }
  };
  // Any point of either feature moves at most as far as its farthest node, so the pair
  // closes in by at most twice the largest node displacement.
  const auto out_of_reach = [&](double start_distance, const std::array<int, 4>& nodes) {
    double reach = 0.0;
    for (int k : nodes) reach = std::max(reach, v[k].squaredNorm());
    return start_distance - 2.0 * h * std::sqrt(reach) > eps;
  };

#pragma omp parallel if (pt_pairs.size() + ee_pairs.size() > kParallelThreshold)
  {
    std::vector<Keyed> local;
#pragma omp for schedule(dynamic, 1024) nowait
    for (long p = 0; p < static_cast<long>(pt_pairs.size()); ++p) {
      const auto [k, t] = pt_pairs[p];
      const auto& tri = m_triangles[t];
      const std::array<int, 4> nodes{k, tri[0], tri[1], tri[2]};
      if (skip(nodes) || out_of_reach(m_pt_distance[p], nodes)) continue;
      std::array<Eigen::Vector3d, 4> x, d;
      motion(nodes, x, d);
      // |det| = 2 area * distance from the plane: the tolerance is eps in distance.
      const double area2 =
          std::max((x[2] - x[1]).cross(x[3] - x[1]).norm(),
                   (x[2] + d[2] - x[1] - d[1]).cross(x[3] + d[3] - x[1] - d[1]).norm());
      const auto roots = coplanarity_times(x, d, eps * area2);
      for (int r = 0; r < roots.count; ++r) {
        std::array<Eigen::Vector3d, 4> y;
        for (int i = 0; i < 4; ++i) y[i] = x[i] + roots.times[r] * d[i];
        const auto closest = geometry::closest_point_on_triangle(y[0], {y[1], y[2], y[3]});
        if ((y[0] - closest.point).norm() >= eps) continue;
        Eigen::Vector3d n = (y[2] - y[1]).cross(y[3] - y[1]);
        if (n.norm() == 0.0) continue;
        n.normalize();
        const Eigen::Vector3d& w = closest.barycentric;
        const double side = (x[0] - (w[0] * x[1] + w[1] * x[2] + w[2] * x[3])).dot(n);
        if (side < 0.0) n = -n;
        local.push_back({{0, k, t}, Contact{nodes, {1.0, -w[0], -w[1], -w[2]}, n, target}});
        break;
      }
    }
#pragma omp for schedule(dynamic, 1024) nowait
    for (long p = 0; p < static_cast<long>(ee_pairs.size()); ++p) {
      const auto [e, f] = ee_pairs[p];
      const std::array<int, 4> nodes{edges[e][0], edges[e][1], edges[f][0], edges[f][1]};
      if (skip(nodes) || out_of_reach(m_ee_distance[p], nodes)) continue;
      std::array<Eigen::Vector3d, 4> x, d;
      motion(nodes, x, d);
      // |det| = |e1 x e2| * distance between the lines; the floor keeps near-parallel
      // edges (whose det is round-off) from reporting every time.
      const double cross =
          std::max((x[1] - x[0]).cross(x[3] - x[2]).norm(),
                   (x[1] + d[1] - x[0] - d[0]).cross(x[3] + d[3] - x[2] - d[2]).norm());
      const double lengths = (x[1] - x[0]).norm() * (x[3] - x[2]).norm();
      const auto roots = coplanarity_times(x, d, eps * std::max(cross, 1e-6 * lengths));
      for (int r = 0; r < roots.count; ++r) {
        std::array<Eigen::Vector3d, 4> y;
        for (int i = 0; i < 4; ++i) y[i] = x[i] + roots.times[r] * d[i];
        const auto closest = geometry::closest_segment_segment(y[0], y[1], y[2], y[3]);
        const double s = closest.s, u = closest.t;
        const Eigen::Vector3d pa = (1 - s) * y[0] + s * y[1], pb = (1 - u) * y[2] + u * y[3];
        if (std::sqrt(closest.distance2) >= eps) continue;
        Eigen::Vector3d n = (y[1] - y[0]).cross(y[3] - y[2]);
        if (n.norm() <= 1e-12 * (y[1] - y[0]).norm() * (y[3] - y[2]).norm()) n = pa - pb;
        if (n.norm() == 0.0) continue;
        n.normalize();
        const double side = (((1 - s) * x[0] + s * x[1]) - ((1 - u) * x[2] + u * x[3])).dot(n);
        if (side < 0.0) n = -n;
        local.push_back({{1, e, f}, Contact{nodes, {1 - s, s, -(1 - u), -u}, n, target}});
        break;
      }
    }
#pragma omp critical
    keyed.insert(keyed.end(), local.begin(), local.end());
  }
  // Thread order must not change the result: contacts are applied in pair order.
  std::sort(keyed.begin(), keyed.end(),
            [](const Keyed& a, const Keyed& b) { return a.first < b.first; });
  out.clear();
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
  m_candidates_valid = false;  // a new step: new start positions

  // 1. Proximity at the start of the step.
  update_candidates(x0, v, h, stats);
  std::vector<Contact> contacts;
  proximity_contacts(x0, v, inverse_mass, h, contacts);
  for (const auto& c : contacts) apply(c, v, inverse_mass, m_friction);
  stats.proximity_contacts = static_cast<int>(contacts.size());

  // 2. Continuous collision passes over the swept candidates.
  std::vector<char> active(n, 1);
  bool colliding = false;
  for (int pass = 0; pass < m_ccd_passes; ++pass) {
    update_candidates(x0, v, h, stats);
    ccd_contacts(x0, v, inverse_mass, h, pass == 0 ? nullptr : &active, contacts);
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
    update_candidates(x0, v, h, stats);
    ccd_contacts(x0, v, inverse_mass, h, nullptr, contacts);
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
