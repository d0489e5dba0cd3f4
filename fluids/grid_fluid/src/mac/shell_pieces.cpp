#include "shellflow/grid_fluid/mac/shell_pieces.hpp"

#include <algorithm>
#include <cmath>

#include <omp.h>

#include <Eigen/Geometry>

#include "shellflow/geometry/convex_polygon.hpp"
#include "shellflow/geometry/triangle_distance.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

std::vector<ShellPiece> shell_pieces(const ShellGeometry& shells, const grid::UniformGrid& grid,
                                     const CellParts& parts) {
  std::vector<ShellPiece> pieces;
  if (parts.parts().empty()) return pieces;
  const double dx = grid.dx();
  const Eigen::Vector3d origin = grid.origin();
  const Eigen::Vector3i cells = grid.cells();
  // Each side's part is the one a point just off the piece sees: beyond the wedge (ε thick).
  const double off = 2.0 * shells.epsilon();
  std::vector<std::vector<ShellPiece>> found(omp_get_max_threads());
  for (int s = 0; s < shells.shell_count(); ++s) {
    const geometry::TriangleMesh& mesh = shells.mesh(s);
    const int count = mesh.triangle_count();
#pragma omp parallel for schedule(dynamic, 64)
    for (int t = 0; t < count; ++t) {
      const geometry::TriangleCorners c = mesh.corners(t);
      const Eigen::Vector3d twice_area = (c[1] - c[0]).cross(c[2] - c[0]);
      if (twice_area.squaredNorm() == 0.0) continue;
      const Eigen::Vector3d normal = twice_area.normalized();
      Eigen::Vector3d lo = c[0].cwiseMin(c[1]).cwiseMin(c[2]);
      Eigen::Vector3d hi = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
      Eigen::Vector3i first, last;
      for (int d = 0; d < 3; ++d) {
        first[d] = std::max(0, static_cast<int>(std::floor((lo[d] - origin[d]) / dx)));
        last[d] = std::min(cells[d] - 1, static_cast<int>(std::floor((hi[d] - origin[d]) / dx)));
      }
      const geometry::ConvexPolygon triangle = geometry::ConvexPolygon::triangle(c);
      for (int k = first.z(); k <= last.z(); ++k)
        for (int j = first.y(); j <= last.y(); ++j)
          for (int i = first.x(); i <= last.x(); ++i) {
            const std::int64_t cell = grid.index(Location::Cell, i, j, k);
            if (parts.parts_of(cell).empty()) continue;  // a whole cell: its pieces' flux cancels
            const Eigen::Vector3d low = origin + dx * Eigen::Vector3d(i, j, k);
            const auto [area, centroid] = geometry::moments(
                geometry::clip_to_box(triangle, low, low + Eigen::Vector3d::Constant(dx)));
            if (area == 0.0) continue;
            ShellPiece piece;
            piece.cell = cell;
            piece.area = area / (dx * dx);
            piece.normal = normal;
            piece.centroid.shell = s;
            piece.centroid.triangle = t;
            piece.centroid.barycentric =
                geometry::closest_point_on_triangle(centroid, c).barycentric;
            piece.front = parts.part_seen_from(shells, grid, cell, centroid + off * normal);
            piece.back = parts.part_seen_from(shells, grid, cell, centroid - off * normal);
            found[omp_get_thread_num()].push_back(piece);
          }
    }
  }
  for (const auto& list : found) pieces.insert(pieces.end(), list.begin(), list.end());
  std::sort(pieces.begin(), pieces.end(), [](const ShellPiece& p, const ShellPiece& q) {
    if (p.cell != q.cell) return p.cell < q.cell;
    if (p.centroid.shell != q.centroid.shell) return p.centroid.shell < q.centroid.shell;
    return p.centroid.triangle < q.centroid.triangle;
  });
  return pieces;
}

std::vector<Eigen::Vector3d> shell_flux(const ShellGeometry& shells,
                                        std::span<const ShellPiece> pieces, size_t part_count) {
  std::vector<Eigen::Vector3d> flux(part_count, Eigen::Vector3d::Zero());
  for (const ShellPiece& piece : pieces) {
    // The normal points out of the back part and into the front one.
    const Eigen::Vector3d swept =
        piece.area * shells.velocity_at(piece.centroid).cwiseProduct(piece.normal);
    if (piece.back >= 0) flux[piece.back] += swept;
    if (piece.front >= 0) flux[piece.front] -= swept;
  }
  return flux;
}

}  // namespace shellflow::grid_fluid
