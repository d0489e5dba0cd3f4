// Self-collision culling by normal cones (self_collision_hierarchy.hpp): flat patches
// yield no pairs, and every pair that can collide is still found: two parallel sheets
// (same normals, not connected), a ribbon curled flat onto itself (same normals,
// connected, but its boundary overlaps in projection) and a sheet folding over during
// the step (its normals turn over). Culling must also keep every pair of features
// within the contact distance: a crease whose sides come within it, and a ribbon curled
// almost closed with a gap below it. The hierarchy keeps the patches of the rest shape
// when obstacles come and go.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "mass_spring_cloth/contact_broad_phase.hpp"
#include "mass_spring_cloth/self_collision_hierarchy.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/geometry/triangle_distance.hpp"

namespace shellflow::cloth {
namespace {

using Vectors = std::vector<Eigen::Vector3d>;
using Triangles = std::vector<std::array<int, 3>>;
using PairSet = std::set<std::array<int, 2>>;

struct Mesh {
  Vectors x;
  Triangles triangles;
};

// nu x nv grid in the x-y plane, spacing 1 cm, lower-left corner at `origin`.
Mesh grid(int nu, int nv, const Eigen::Vector3d& origin = Eigen::Vector3d::Zero()) {
  const auto g = geometry::make_grid(0.01 * (nu - 1), 0.01 * (nv - 1), nu, nv,
                                     geometry::GridPattern::Herringbone);
  Mesh m;
  for (int k = 0; k < g.positions.rows(); ++k)
    m.x.push_back(g.positions.row(k).transpose() - g.positions.row(0).transpose() + origin);
  for (int t = 0; t < g.triangles.rows(); ++t)
    m.triangles.push_back({g.triangles(t, 0), g.triangles(t, 1), g.triangles(t, 2)});
  return m;
}

void append(Mesh& to, const Mesh& from) {
  const int offset = static_cast<int>(to.x.size());
  to.x.insert(to.x.end(), from.x.begin(), from.x.end());
  for (const auto& t : from.triangles)
    to.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

std::vector<geometry::Aabb> swept_boxes(const Mesh& m, const Vectors& a, const Vectors& b,
                                        double pad) {
  std::vector<geometry::Aabb> boxes;
  for (const auto& t : m.triangles) {
    geometry::Aabb box;
    for (int k : t) box.extend(a[k]), box.extend(b[k]);
    boxes.push_back(box.inflated(pad));
  }
  return boxes;
}

struct Found {
  PairSet pairs;  ///< reported, as (low, high)
  PairSet brute;  ///< all overlapping pairs, by testing every pair
  size_t reported = 0;
};

Found find_pairs(const Mesh& m, const Vectors& a, const Vectors& b, double pad) {
  const auto boxes = swept_boxes(m, a, b, pad);
  SelfCollisionHierarchy hierarchy;
  hierarchy.build(m.triangles, a);
  hierarchy.update(boxes, a, b);
  std::vector<std::array<int, 2>> out;
  hierarchy.self_pairs(a, b, 2.0 * pad, out);
  Found f;
  f.reported = out.size();
  for (const auto& [s, t] : out) f.pairs.insert({std::min(s, t), std::max(s, t)});
  for (size_t s = 0; s < boxes.size(); ++s)
    for (size_t t = s + 1; t < boxes.size(); ++t)
      if (boxes[s].overlaps(boxes[t])) f.brute.insert({static_cast<int>(s), static_cast<int>(t)});
  return f;
}

// Pad of the boxes as the solver inflates them: (thickness + 2 reuse margins of a
// quarter thickness) / 2 = 0.75 thickness (collision_solver.cpp), with the default
// thickness, a quarter of the mean edge (mass_spring_cloth.cpp): (2 + sqrt 2) / 3 cm
// here, two axis edges and one diagonal per 1 cm cell.
constexpr double kPad = 0.75 * 0.25 * 0.01 * (2.0 + M_SQRT2) / 3.0;

TEST(ClothSelfCollisionCulling, FlatAndGentlyCurvedSheetsYieldNoPairs) {
  auto m = grid(21, 31);
  auto f = find_pairs(m, m.x, m.x, kPad);
  EXPECT_EQ(f.reported, 0u);
  // What a box test alone would leave: at least the pairs across each interior edge,
  // (3 x 1200 triangles - 100 boundary edges) / 2.
  EXPECT_GE(f.brute.size(), 1750u);
  // Bent into a quarter cylinder (normals turn through 90 degrees, less than 180), and
  // moving a little during the step.
  Vectors a = m.x, b = m.x;
  for (size_t k = 0; k < a.size(); ++k) {
    const double angle = 0.5 * M_PI * m.x[k].x() / 0.2, radius = 0.2 / (0.5 * M_PI);
    a[k] = Eigen::Vector3d(radius * std::sin(angle), m.x[k].y(), radius * (1 - std::cos(angle)));
    b[k] = a[k] + Eigen::Vector3d(0.0, 0.0, 0.002 * std::sin(10 * m.x[k].y()));
  }
  f = find_pairs(m, a, b, kPad);
  EXPECT_EQ(f.reported, 0u);
}

TEST(ClothSelfCollisionCulling, ParallelSheetsAreNotCulled) {
  // Two 10 x 10 sheets 1 mm apart with the same normal: one mesh, not connected.
  auto m = grid(11, 11);
  append(m, grid(11, 11, Eigen::Vector3d(0.003, 0.002, 0.001)));
  const int lower_triangles = 200;
  const auto f = find_pairs(m, m.x, m.x, kPad);
  EXPECT_EQ(f.reported, f.pairs.size());  // no pair twice
  int between = 0;
  for (const auto& p : f.brute)
    if (p[0] < lower_triangles && p[1] >= lower_triangles) {
      EXPECT_TRUE(f.pairs.count(p)) << "pair " << p[0] << ", " << p[1];
      ++between;
    }
  // Each of the 200 lower triangles has its centroid (a third of a cell from its sides,
  // beyond the 3 mm x 2 mm offset) under the upper sheet, 1 mm < 2 kPad away.
  EXPECT_GE(between, 200);
  for (const auto& p : f.pairs) EXPECT_TRUE(f.brute.count(p));
}

TEST(ClothSelfCollisionCulling, RibbonCurledOntoItselfIsNotCulled) {
  // A flat ribbon wound 1.25 turns around the z axis, rising 1 mm per turn: every normal
  // is within a degree of +z and the ribbon is one disc, but its last quarter lies 1 mm
  // above its first: only the boundary test can tell.
  const int nu = 126, nv = 3;
  auto m = grid(nu, nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double angle = 2.5 * M_PI * i / (nu - 1), radius = 0.2 + 0.01 * j;
      m.x[i + nu * j] = Eigen::Vector3d(radius * std::cos(angle), radius * std::sin(angle),
                                        0.001 * angle / (2 * M_PI));
    }
  const auto f = find_pairs(m, m.x, m.x, kPad);
  // Triangles of columns a turn apart (100 columns): all overlapping pairs are found.
  const auto column = [&](int t) {
    const auto& tri = m.triangles[t];
    return std::min({tri[0] % nu, tri[1] % nu, tri[2] % nu});
  };
  int across_turns = 0;
  for (const auto& p : f.brute)
    if (std::abs(column(p[0]) - column(p[1])) > 50) {
      EXPECT_TRUE(f.pairs.count(p)) << "pair " << p[0] << ", " << p[1];
      ++across_turns;
    }
  // Each of the 100 triangles of the last 25 columns lies 1 mm above its counterpart.
  EXPECT_GE(across_turns, 100);
}

TEST(ClothSelfCollisionCulling, SheetFoldingOverDuringTheStepIsNotCulled) {
  // Flat at the start; at the end its right half has turned over onto its left half,
  // 1 mm above. Start and end are each flat, but the right half's normals turn over.
  auto m = grid(21, 11);
  Vectors b = m.x;
  for (auto& p : b)
    if (p.x() > 0.1) p = Eigen::Vector3d(0.2 - p.x(), p.y(), 0.001);
  const auto f = find_pairs(m, m.x, b, kPad);
  // Nodes on the fold line x = 10 cm count as left: 1e-9 m lies far above the grid's
  // round-off (1e-17 m) and far below its 1 cm spacing.
  const auto right = [&](int t) {
    for (int k : m.triangles[t])
      if (m.x[k].x() > 0.1 + 1e-9) return true;
    return false;
  };
  int between = 0;
  for (const auto& p : f.brute)
    if (right(p[0]) != right(p[1])) {
      EXPECT_TRUE(f.pairs.count(p)) << "pair " << p[0] << ", " << p[1];
      ++between;
    }
  // Each of the 200 right triangles ends 1 mm above its mirror image on the left.
  EXPECT_GE(between, 200);
}

// Every point-triangle and edge-edge pair of non-adjacent features closer than
// `distance` at the positions x (brute force over all pairs) must be among the broad
// phase's candidates; returns how many such pairs there are. Nodes from `cloth_nodes`
// on are an obstacle's (pairs of only those never count; without self-collision a pair
// counts only with one of them).
int expect_all_close_pairs_found(const Mesh& m, double distance, int cloth_nodes = -1,
                                 bool self_collision = true) {
  ContactBroadPhase broad_phase;
  const int n = static_cast<int>(m.x.size());
  if (cloth_nodes < 0) cloth_nodes = n;
  broad_phase.set_topology(m.triangles, cloth_nodes, self_collision, m.x);
  const auto counts = [&](std::initializer_list<int> nodes) {
    int obstacle = 0;
    for (int k : nodes) obstacle += k >= cloth_nodes;
    return obstacle < static_cast<int>(nodes.size()) && (self_collision || obstacle > 0);
  };
  ContactCandidates candidates;
  broad_phase.find(m.x, m.x, distance, candidates);
  const std::set<std::array<int, 2>> pt(candidates.point_triangle.begin(),
                                        candidates.point_triangle.end());
  const std::set<std::array<int, 2>> ee(candidates.edge_edge.begin(), candidates.edge_edge.end());
  int close = 0;
  for (int k = 0; k < n; ++k)
    for (int t = 0; t < static_cast<int>(m.triangles.size()); ++t) {
      const auto& tri = m.triangles[t];
      if (tri[0] == k || tri[1] == k || tri[2] == k || !counts({k, tri[0], tri[1], tri[2]}))
        continue;
      const geometry::TriangleCorners c{m.x[tri[0]], m.x[tri[1]], m.x[tri[2]]};
      if ((m.x[k] - geometry::closest_point_on_triangle(m.x[k], c).point).norm() >= distance)
        continue;
      ++close;
      EXPECT_TRUE(pt.count({k, t})) << "node " << k << ", triangle " << t;
    }
  const auto& edges = broad_phase.edges();
  for (int e = 0; e < static_cast<int>(edges.size()); ++e)
    for (int f = e + 1; f < static_cast<int>(edges.size()); ++f) {
      const auto &p = edges[e], &q = edges[f];
      if (p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1] ||
          !counts({p[0], p[1], q[0], q[1]}))
        continue;
      const auto closest =
          geometry::closest_segment_segment(m.x[p[0]], m.x[p[1]], m.x[q[0]], m.x[q[1]]);
      if (closest.distance2 >= distance * distance) continue;
      ++close;
      EXPECT_TRUE(ee.count({e, f})) << "edges " << e << ", " << f;
    }
  return close;
}

TEST(ClothSelfCollisionCulling, CreaseWithinTheThicknessKeepsItsClosePairs) {
  // A 21 x 11 sheet folded along x = 10 cm into a V with 80 degrees between its sides
  // (normals 50 degrees either side of the axis, inside the 60-degree cone), with the
  // thickness equal to the 1 cm spacing: features two rings apart across the crease,
  // and one ring apart along the flat sides, are within the solver's contact distance
  // (thickness + 2 margins of thickness / 4, collision_solver.cpp).
  auto m = grid(21, 11);
  const double side = 50.0 * M_PI / 180.0;
  for (auto& p : m.x) {
    const double r = std::abs(p.x() - 0.1);
    p = Eigen::Vector3d(0.1 + std::copysign(r * std::sin(side), p.x() - 0.1), p.y(),
                        r * std::cos(side));
  }
  const double thickness = 0.01;
  // At least one per interior node (19 x 9): each is within a spacing (< 1.5 cm) of the
  // triangles beyond the far sides of its own.
  EXPECT_GE(expect_all_close_pairs_found(m, 1.5 * thickness), 171);
}

TEST(ClothSelfCollisionCulling, RibbonCurledAlmostClosedKeepsItsGap) {
  // A flat ribbon bent in its plane into an annulus whose two ends are 2 mm apart, with
  // the default thickness of a quarter of the 1 cm spacing: every normal is +z, every
  // triangle is well shaped, and the boundary crosses nowhere, but the ends are within
  // the contact distance 1.5 x 2.5 mm.
  const int nu = 64, nv = 3;
  auto m = grid(nu, nv);
  const double radius = 0.1, gap = 0.002;
  const double turn = 2.0 * M_PI - gap / radius;  // the ends' angle apart
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double angle = turn * i / (nu - 1), r = radius + 0.01 * j;
      m.x[i + nu * j] = Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), 0.0);
    }
  const double thickness = 0.0025;
  // At least the two pairs of facing end edges, 2 to 2.4 mm apart.
  EXPECT_GE(expect_all_close_pairs_found(m, 1.5 * thickness), 2);
}

TEST(ClothSelfCollisionCulling, ObstacleQueriesFindEveryClosePair) {
  // A 10 x 10 cm cloth 2 mm above a 33 x 33 cm obstacle sheet of 2178 triangles (enough
  // for the parallel obstacle queries), default thickness 2.5 mm: with and without
  // self-collision, every cloth-obstacle pair within 1.5 thicknesses is a candidate.
  auto m = grid(11, 11, Eigen::Vector3d(0.1, 0.1, 0.0));
  const int cloth_nodes = static_cast<int>(m.x.size());
  append(m, grid(34, 34, Eigen::Vector3d(0.0, 0.0, -0.002)));
  const double distance = 1.5 * 0.0025;
  const int close = expect_all_close_pairs_found(m, distance, cloth_nodes, false);
  EXPECT_GE(close, 121);  // each cloth node 2 mm above an obstacle triangle
  EXPECT_EQ(expect_all_close_pairs_found(m, distance, cloth_nodes, true), close);
}

TEST(ClothSelfCollisionCulling, HierarchyKeepsTheRestShapeWhenObstaclesChange) {
  // A 40 x 10 cm sheet, flat at rest, is crumpled (folded like an accordion into 5 cm
  // panels 1 mm apart) when an obstacle triangle appears, then bent into a sharp V
  // along x = 20 cm (sides 75 degrees either side of +z: the whole sheet fails the cone
  // test). The rest shape's hierarchy splits the sheet first at x = 20 cm (the median
  // along its widest extent), so each side of the V is one culled patch and no pair has
  // both features on one side. A hierarchy shaped by the accordion would split across y
  // first and leave pairs between patches of the same side.
  auto m = grid(41, 11);
  const int cloth_nodes = static_cast<int>(m.x.size());
  const Vectors rest = m.x;
  Vectors x = rest;
  for (auto& p : x) {
    const int panel = static_cast<int>(p.x() / 0.05 + 1e-9);
    const double u = p.x() - 0.05 * panel;
    p = Eigen::Vector3d(panel % 2 == 0 ? u : 0.05 - u, p.y(), 0.001 * panel);
  }
  ContactBroadPhase broad_phase;
  broad_phase.set_topology(m.triangles, cloth_nodes, true, rest);
  ContactCandidates candidates;
  broad_phase.find(x, x, 2.0 * kPad, candidates);
  // An obstacle triangle 1 m away: the set of solids changes while the sheet is folded.
  auto with_obstacle = m.triangles;
  with_obstacle.push_back({cloth_nodes, cloth_nodes + 1, cloth_nodes + 2});
  for (const auto& p :
       {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1.1, 1, 1), Eigen::Vector3d(1, 1.1, 1)})
    x.push_back(p);
  broad_phase.set_topology(with_obstacle, cloth_nodes, true, rest);
  broad_phase.find(x, x, 2.0 * kPad, candidates);
  const double side_angle = 75.0 * M_PI / 180.0;
  for (int k = 0; k < cloth_nodes; ++k) {
    const double r = rest[k].x() - 0.2;
    x[k] = Eigen::Vector3d(0.2 + r * std::cos(side_angle), rest[k].y(),
                           std::abs(r) * std::sin(side_angle));
  }
  broad_phase.find(x, x, 2.0 * kPad, candidates);
  EXPECT_EQ(broad_phase.culled_patches(), 2);
  // Sides by rest x; nodes on the crease (within round-off, 1e-9 m) are on neither.
  const auto side = [&](int k) {
    return rest[k].x() < 0.2 - 1e-9 ? -1 : (rest[k].x() > 0.2 + 1e-9 ? 1 : 0);
  };
  int across = 0;
  for (const auto& [k, t] : candidates.point_triangle) {
    const auto& tri = m.triangles[t];
    const int s = side(tri[0]) + side(tri[1]) + side(tri[2]);  // nonzero: the side
    EXPECT_FALSE(side(k) != 0 && s * side(k) > 0) << "node " << k << ", triangle " << t;
    across += side(k) * s < 0;
  }
  EXPECT_GT(across, 0);  // the V's sides meet within the distance along the crease
}

}  // namespace
}  // namespace shellflow::cloth
