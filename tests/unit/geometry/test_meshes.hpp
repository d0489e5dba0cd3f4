#pragma once
// Small closed and open meshes for the geometry tests and benchmark, built here so the
// tests do not depend on the scene-file mesh generators. Vertices shared between faces
// are welded (one node), so closed meshes are watertight exactly.

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::geometry::test {

struct Mesh {
  sdk::Positions positions;
  sdk::Triangles triangles;
};

inline Mesh from_lists(const std::vector<Eigen::Vector3d>& x,
                       const std::vector<Eigen::Vector3i>& t) {
  Mesh m;
  m.positions.resize(static_cast<int>(x.size()), 3);
  m.triangles.resize(static_cast<int>(t.size()), 3);
  for (int i = 0; i < static_cast<int>(x.size()); ++i) m.positions.row(i) = x[i].transpose();
  for (int i = 0; i < static_cast<int>(t.size()); ++i) m.triangles.row(i) = t[i].transpose();
  return m;
}

/// Icosphere of radius r: the icosahedron split `levels` times, outward normals.
inline Mesh make_icosphere(double r, int levels) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> x = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                    {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                    {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& p : x) p = r * p.normalized();
  std::vector<Eigen::Vector3i> t = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> mid;
    const auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      x.push_back(r * (x[a] + x[b]).normalized());
      const int id = static_cast<int>(x.size()) - 1;
      mid.emplace(key, id);
      return id;
    };
    std::vector<Eigen::Vector3i> next;
    for (const auto& f : t) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    t = next;
  }
  return from_lists(x, t);
}

/// Closed axis-aligned box [-h, h] (h = size/2), each face split into d x d quads of two
/// triangles, outward normals. Nodes come from an integer lattice so shared ones weld.
inline Mesh make_closed_box(const Eigen::Vector3d& size, int d) {
  std::map<std::tuple<int, int, int>, int> ids;
  std::vector<Eigen::Vector3d> x;
  std::vector<Eigen::Vector3i> t;
  const auto node = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    const auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    x.push_back({size.x() * (double(i) / d - 0.5), size.y() * (double(j) / d - 0.5),
                 size.z() * (double(k) / d - 0.5)});
    ids.emplace(key, static_cast<int>(x.size()) - 1);
    return static_cast<int>(x.size()) - 1;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int a = 0; a < d; ++a) {
        for (int b = 0; b < d; ++b) {
          const auto lattice = [&](int da, int db) {
            int c[3];
            c[axis] = side * d;
            c[u] = a + da;
            c[v] = b + db;
            return node(c[0], c[1], c[2]);
          };
          const int n00 = lattice(0, 0), n10 = lattice(1, 0), n11 = lattice(1, 1),
                    n01 = lattice(0, 1);
          // u × v = +axis: counter-clockwise seen from +axis on the far side.
          if (side == 1) {
            t.push_back({n00, n10, n11});
            t.push_back({n00, n11, n01});
          } else {
            t.push_back({n00, n11, n10});
            t.push_back({n00, n01, n11});
          }
        }
      }
    }
  }
  return from_lists(x, t);
}

/// A flat sheet over [0, w] x [0, h] at z = 0 with (nu x nv) nodes, alternating diagonals.
inline Mesh make_sheet(double w, double h, int nu, int nv) {
  std::vector<Eigen::Vector3d> x;
  std::vector<Eigen::Vector3i> t;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) x.push_back({w * i / (nu - 1), h * j / (nv - 1), 0.0});
  }
  for (int j = 0; j + 1 < nv; ++j) {
    for (int i = 0; i + 1 < nu; ++i) {
      const int a = i + nu * j, b = a + 1, c = a + nu, d = c + 1;
      if ((i + j) % 2 == 0) {
        t.push_back({a, b, d});
        t.push_back({a, d, c});
      } else {
        t.push_back({a, b, c});
        t.push_back({b, d, c});
      }
    }
  }
  return from_lists(x, t);
}

/// A cloth folded over onto itself: a (2n-1) x n sheet whose first half lies on z = 0
/// over [0, 1]^2 and whose second half comes back over it at z = gap (sharp fold at x = 1).
inline Mesh make_folded_cloth(int n, double gap) {
  Mesh m = make_sheet(2.0, 1.0, 2 * n - 1, n);
  for (int i = 0; i < m.positions.rows(); ++i) {
    const double u = m.positions(i, 0);
    if (u > 1.0) {
      m.positions(i, 0) = 2.0 - u;
      m.positions(i, 2) = gap;
    }
  }
  return m;
}

}  // namespace shellflow::geometry::test
