#include "shellflow/grid_fluid/pressure/rigid_face_areas.hpp"

#include "shellflow/grid_fluid/mac/mac_grid.hpp"

#include <Eigen/Geometry>

#include "shellflow/geometry/convex_polygon.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace shellflow::grid_fluid {

namespace {

std::int64_t column_key(int b, int c) {
  return static_cast<std::int64_t>((static_cast<std::uint64_t>(static_cast<std::uint32_t>(b)) << 32) |
                                   static_cast<std::uint32_t>(c));
}

constexpr double kSameSheet = 0.7071;  // cos 45°

}  // namespace

std::vector<RigidFacePieces> rigid_face_pieces(const grid::UniformGrid& grid,
                                               const sdk::ShellSurface& shell,
                                               const Eigen::Vector3d& centre_of_mass,
                                               const std::vector<RigidFaceCut>& cuts) {
  const double dx = grid.dx();
  const Eigen::Vector3d& origin = grid.origin();
  const Eigen::Vector3i& cells = grid.cells();
  std::vector<RigidFacePieces> result(cuts.size());
  const auto& T = *shell.triangles;
  const auto& x = shell.positions;
  const auto corner = [&](int t, int v) -> Eigen::Vector3d { return x.row(T(t, v)).transpose(); };
  const auto unit_normal = [&](int t) {
    return (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0)).normalized();
  };
  std::vector<Eigen::Vector3d> cut_point(cuts.size()), cut_normal(cuts.size());
  // The cuts of each column across each axis.
  std::array<std::unordered_map<std::int64_t, std::vector<int>>, 3> column;
  for (size_t k = 0; k < cuts.size(); ++k) {
    const int a = cuts[k].axis;
    cut_point[k] = grid.position(face_location(a), cuts[k].face);
    cut_point[k][a] = cuts[k].crossing;
    cut_normal[k] = unit_normal(cuts[k].triangle);
    if (cut_normal[k][a] < 0.0) cut_normal[k] = -cut_normal[k];  // towards the face's + side
    column[a][column_key(cuts[k].face[(a + 1) % 3], cuts[k].face[(a + 2) % 3])].push_back(
        static_cast<int>(k));
  }
  // The nearest cut of column (i, j) across a on the sheet of a piece at p of normal n.
  const auto nearest_cut = [&](int a, int i, int j, const Eigen::Vector3d& p,
                               const Eigen::Vector3d& n, int& best, double& distance) {
    const auto found = column[a].find(column_key(i, j));
    if (found == column[a].end()) return;
    for (const int k : found->second) {
      if (std::abs(n.dot(cut_normal[k])) < kSameSheet) continue;
      if (std::abs((p - cut_point[k]).dot(cut_normal[k])) > dx) continue;
      const double d = (p - cut_point[k]).norm();
      if (d < distance) {
        best = k;
        distance = d;
      }
    }
  };
  // Every piece must find a face, or a closed shell's inside would push on it with the
  // vector area of what was left (a constant pressure with a net force, which pumped energy
  // into a closed box thrown through still air): failing its column and the eight beside,
  // the nearest cut on its sheet, of any axis.
  const auto nearest_anywhere = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    int best = -1;
    double distance = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < cuts.size(); ++k) {
      const double d = (p - cut_point[k]).norm();
      if (d < distance && std::abs(n.dot(cut_normal[k])) >= kSameSheet) {
        best = static_cast<int>(k);
        distance = d;
      }
    }
    return best;
  };
  for (int t = 0; t < shell.triangle_count(); ++t) {
    const geometry::ConvexPolygon tri =
        geometry::ConvexPolygon::triangle({corner(t, 0), corner(t, 1), corner(t, 2)});
    const Eigen::Vector3d twice_area = (tri.corner[1] - tri.corner[0]).cross(tri.corner[2] - tri.corner[0]);
    if (twice_area.squaredNorm() == 0.0) continue;
    const Eigen::Vector3d n = twice_area.normalized();
    int a = 0;
    n.cwiseAbs().maxCoeff(&a);
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    // The shell's velocity at a point of the triangle (barycentric: exact for a rigid body).
    const Eigen::Vector3d u0 = shell.velocities.row(T(t, 0)).transpose();
    const Eigen::Vector3d u1 = shell.velocities.row(T(t, 1)).transpose();
    const Eigen::Vector3d u2 = shell.velocities.row(T(t, 2)).transpose();
    const double inverse = 1.0 / twice_area.squaredNorm();
    const Eigen::Vector3d e1 = tri.corner[1] - tri.corner[0], e2 = tri.corner[2] - tri.corner[0];
    const auto velocity_at = [&](const Eigen::Vector3d& p) {
      const Eigen::Vector3d d = p - tri.corner[0];
      const double l1 = d.cross(e2).dot(twice_area) * inverse;
      const double l2 = e1.cross(d).dot(twice_area) * inverse;
      return Eigen::Vector3d((1.0 - l1 - l2) * u0 + l1 * u1 + l2 * u2);
    };
    Eigen::Vector3d lo = tri.corner[0], hi = tri.corner[0];
    for (int v = 1; v < 3; ++v) {
      lo = lo.cwiseMin(tri.corner[v]);
      hi = hi.cwiseMax(tri.corner[v]);
    }
    Eigen::Vector3i first, last;
    for (int d = 0; d < 3; ++d) {
      first[d] = std::max(0, static_cast<int>(std::floor((lo[d] - origin[d]) / dx)));
      last[d] = std::min(cells[d] - 1, static_cast<int>(std::floor((hi[d] - origin[d]) / dx)));
    }
    for (int i = first[b]; i <= last[b]; ++i) {
      const double bl = origin[b] + i * dx;
      const geometry::ConvexPolygon strip =
          geometry::clip(geometry::clip(tri, b, bl, 1.0), b, bl + dx, -1.0);
      if (strip.count < 3) continue;
      for (int j = first[c]; j <= last[c]; ++j) {
        const double cl = origin[c] + j * dx;
        const geometry::ConvexPolygon bar =
            geometry::clip(geometry::clip(strip, c, cl, 1.0), c, cl + dx, -1.0);
        if (bar.count < 3) continue;
        for (int l = first[a]; l <= last[a]; ++l) {
          const double al = origin[a] + l * dx;
          const geometry::ConvexPolygon piece =
              geometry::clip(geometry::clip(bar, a, al, 1.0), a, al + dx, -1.0);
          if (piece.count < 3) continue;
          const auto [area, centroid] = geometry::moments(piece);
          if (area == 0.0) continue;
          int best = -1;
          double distance = std::numeric_limits<double>::infinity();
          nearest_cut(a, i, j, centroid, n, best, distance);
          for (int di = -1; di <= 1 && best < 0; ++di)
            for (int dj = -1; dj <= 1; ++dj) nearest_cut(a, i + di, j + dj, centroid, n, best, distance);
          if (best < 0) best = nearest_anywhere(centroid, n);
          if (best < 0) continue;
          // The normal turned to the cut's + side (its sheet's, when the cut's axis is
          // another than the piece's).
          const Eigen::Vector3d towards_plus = n.dot(cut_normal[best]) >= 0.0 ? n : Eigen::Vector3d(-n);
          RigidFacePieces& face = result[best];
          face.vector_area += area * towards_plus;
          face.moment += area * (centroid - centre_of_mass).cross(towards_plus);
          face.flux += area * velocity_at(centroid).dot(towards_plus);
        }
      }
    }
  }
  return result;
}

}  // namespace shellflow::grid_fluid
