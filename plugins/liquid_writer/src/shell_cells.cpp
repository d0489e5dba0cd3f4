#include "shellflow/liquid_writer/shell_cells.hpp"

#include <algorithm>
#include <cmath>

#include "shellflow/geometry/triangle_mesh.hpp"

namespace shellflow::liquid_writer {

namespace {

/// Does the triangle meet the closed box of centre `centre` and half-sizes `half`? The
/// separating-axis test of Akenine-Möller ("Fast 3D triangle-box overlap testing", 2001):
/// the box's 3 face normals, the triangle's normal and the 9 products of their edges.
bool triangle_meets_box(const geometry::TriangleCorners& corners, const Eigen::Vector3d& centre,
                        const Eigen::Vector3d& half) {
  const Eigen::Vector3d v[3] = {corners[0] - centre, corners[1] - centre, corners[2] - centre};
  const auto separated_along = [&](const Eigen::Vector3d& axis) {
    const double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
    const double r = half.dot(axis.cwiseAbs());
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  for (int a = 0; a < 3; ++a)
    if (separated_along(Eigen::Vector3d::Unit(a))) return false;
  const Eigen::Vector3d edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  if (separated_along(edges[0].cross(edges[1]))) return false;
  for (const auto& e : edges)
    for (int a = 0; a < 3; ++a)
      if (separated_along(Eigen::Vector3d::Unit(a).cross(e))) return false;
  return true;
}

}  // namespace

std::vector<Eigen::Vector3i> cells_touched_by_shells(const NodeBox& box, sdk::ShellSet shells) {
  std::vector<Eigen::Vector3i> cells;
  const double radius = 0.5 * std::sqrt(3.0) * box.dx;
  // Grown by 1e-9 Δx: round-off must not lose a cell the triangle touches exactly.
  const Eigen::Vector3d half = Eigen::Vector3d::Constant((0.5 + 1e-9) * box.dx);
  const Eigen::Vector3i last(box.dims[0] - 2, box.dims[1] - 2, box.dims[2] - 2);  // last cell
  if ((last.array() < 0).any()) return cells;
  for (const sdk::ShellSurface& shell : shells) {
    if (!shell.triangles) continue;
    const sdk::Triangles& triangles = *shell.triangles;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
      const geometry::TriangleCorners corners{shell.positions.row(triangles(t, 0)).transpose(),
                                              shell.positions.row(triangles(t, 1)).transpose(),
                                              shell.positions.row(triangles(t, 2)).transpose()};
      Eigen::Vector3d lo = corners[0].cwiseMin(corners[1]).cwiseMin(corners[2]);
      Eigen::Vector3d hi = corners[0].cwiseMax(corners[1]).cwiseMax(corners[2]);
      // Cells whose centre origin + dx (c + ½) lies within `radius` of the box.
      Eigen::Vector3i c_lo, c_hi;
      for (int a = 0; a < 3; ++a) {
        c_lo[a] = std::max(
            0, static_cast<int>(std::ceil((lo[a] - radius - box.origin[a]) / box.dx - 0.5)));
        c_hi[a] = std::min(
            last[a], static_cast<int>(std::floor((hi[a] + radius - box.origin[a]) / box.dx - 0.5)));
      }
      for (int k = c_lo.z(); k <= c_hi.z(); ++k)
        for (int j = c_lo.y(); j <= c_hi.y(); ++j)
          for (int i = c_lo.x(); i <= c_hi.x(); ++i) {
            const Eigen::Vector3d centre =
                box.origin + box.dx * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
            if (triangle_meets_box(corners, centre, half)) cells.emplace_back(i, j, k);
          }
    }
  }
  const auto less = [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(cells.begin(), cells.end(), less);
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}

}  // namespace shellflow::liquid_writer
