#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "shellflow/geometry/mesh_edges.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"

namespace shellflow::grid_fluid {

namespace {

/// The area of [s0, s1] × [t0, t1] where m1 s + m2 t + d >= 0 (a rectangle clipped by a
/// half-plane: Sutherland–Hodgman with one edge, then the shoelace formula).
double rectangle_area_where_positive(double s0, double s1, double t0, double t1, double m1,
                                     double m2, double d) {
  const std::array<Eigen::Vector2d, 4> corners = {Eigen::Vector2d(s0, t0), Eigen::Vector2d(s1, t0),
                                                  Eigen::Vector2d(s1, t1), Eigen::Vector2d(s0, t1)};
  const auto g = [&](const Eigen::Vector2d& p) { return m1 * p.x() + m2 * p.y() + d; };
  std::array<Eigen::Vector2d, 8> kept;
  int count = 0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d& p = corners[k];
    const Eigen::Vector2d& q = corners[(k + 1) % 4];
    const double gp = g(p), gq = g(q);
    if (gp >= 0.0) kept[count++] = p;
    if ((gp >= 0.0) != (gq >= 0.0)) kept[count++] = p + gp / (gp - gq) * (q - p);
  }
  double twice = 0.0;
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector2d& p = kept[k];
    const Eigen::Vector2d& q = kept[(k + 1) % count];
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * std::abs(twice);
}

/// What `make(face, centre)` finds at each interior face of family `axis` that `band`
/// samples (a domain face has one cell and is left out), cast in parallel, in face order.
template <class Entry, class Make>
std::vector<Entry> for_each_interior_band_face(const geometry::ShellBand& band, int axis,
                                               Make&& make) {
  const grid::UniformGrid& grid = band.grid();
  const grid::Location loc = face_location(axis);
  const auto list = band.samples(loc);
  const std::int64_t m = static_cast<std::int64_t>(list.size());
  std::vector<std::vector<Entry>> found(omp_get_max_threads());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < m; ++s) {
    const std::int64_t f = list[s];
    const Eigen::Vector3i ijk = grid.coordinates(loc, f);
    if (ijk[axis] == 0 || ijk[axis] == grid.cells()[axis]) continue;
    if (auto entry = make(f, grid.position(loc, ijk)))
      found[omp_get_thread_num()].push_back(*entry);
  }
  std::vector<Entry> all;
  for (const auto& part : found) all.insert(all.end(), part.begin(), part.end());
  std::sort(all.begin(), all.end(), [](const Entry& x, const Entry& y) { return x.face < y.face; });
  return all;
}

}  // namespace

double open_square_fraction(double m1, double m2, double offset) {
  // Units of Δx, the face's centre at the origin, its side where m1 s + m2 t + offset >= 0.
  if (std::hypot(m1, m2) < 1e-9) return 1.0;  // the plane is parallel to the face
  return rectangle_area_where_positive(-0.5, 0.5, -0.5, 0.5, m1, m2, offset);
}

ShellGeometry::ShellGeometry(sdk::ShellSet shells, double epsilon) : m_epsilon(epsilon) {
  std::vector<const geometry::TriangleBvh*> bvhs;
  for (const auto& surface : shells) {
    if (surface.triangle_count() == 0) {
      m_internal.push_back(-1);
      continue;
    }
    m_internal.push_back(static_cast<int>(m_shells.size()));
    auto shell = std::make_unique<Shell>();
    shell->positions = surface.positions;
    shell->velocities = surface.velocities.rows() == surface.positions.rows()
                            ? surface.velocities
                            : sdk::Positions::Zero(surface.positions.rows(), 3);
    shell->triangles = surface.triangles;
    shell->surface_density = surface.surface_density;
    shell->receives_forces = surface.receives_fluid_forces;
    shell->moves_as_one = surface.receives_fluid_forces && surface.rigid.has_value();
    shell->set_index = static_cast<int>(m_internal.size()) - 1;
    shell->mesh = geometry::TriangleMesh(shell->positions, *shell->triangles);
    shell->bvh = geometry::TriangleBvh(shell->mesh);
    m_shells.push_back(std::move(shell));
  }
  for (const auto& s : m_shells) bvhs.push_back(&s->bvh);
  if (!m_shells.empty()) m_caster = std::make_unique<geometry::WedgeCaster>(bvhs, epsilon);
}

bool ShellGeometry::same_positions(sdk::ShellSet shells) const {
  size_t k = 0;
  for (const auto& surface : shells) {
    if (surface.triangle_count() == 0) continue;
    if (k >= m_shells.size()) return false;
    const auto& mine = m_shells[k++]->positions;
    if (mine.rows() != surface.positions.rows() ||
        !(mine.array() == surface.positions.array()).all())
      return false;
  }
  return k == m_shells.size();
}

void ShellGeometry::set_velocities(std::span<const sdk::Positions> velocities) {
  // `velocities` follows the ShellSet order (which may include empty shells we skipped).
  for (size_t s = 0; s < velocities.size() && s < m_internal.size(); ++s) {
    const int k = m_internal[s];
    if (k < 0 || velocities[s].rows() != m_shells[k]->positions.rows()) continue;
    m_shells[k]->velocities = velocities[s];
  }
}

const std::array<std::vector<CellFaceHit>, 3>& ShellGeometry::cell_face_hits(
    const geometry::ShellBand& band) const {
  if (m_cell_face_hits) return *m_cell_face_hits;
  std::array<std::vector<CellFaceHit>, 3> hits;
  const double half = 0.5 * band.grid().dx();
  for (int a = 0; a < 3; ++a) {
    if (empty()) break;
    hits[a] = for_each_interior_band_face<CellFaceHit>(
        band, a, [&](std::int64_t f, const Eigen::Vector3d& x) -> std::optional<CellFaceHit> {
          Eigen::Vector3d c0 = x, c1 = x;
          c0[a] -= half;
          c1[a] += half;
          if (const auto hit = m_caster->first_hit(c0, c1)) return CellFaceHit{f, *hit};
          return std::nullopt;
        });
  }
  m_cell_face_hits = std::move(hits);
  return *m_cell_face_hits;
}

const std::array<std::vector<FaceAperture>, 3>& ShellGeometry::face_apertures(
    const geometry::ShellBand& band) const {
  if (m_face_apertures) return *m_face_apertures;
  std::array<std::vector<FaceAperture>, 3> apertures;
  const double dx = band.grid().dx();
  // The solves treat a cell as all of one side of the shells, the side of its centre: a
  // face passes the part of its square on that side of the nearest shell's plane. One
  // plane per face: where two shells or a fold cut a square, the nearer one counts. (The
  // part of a cell beyond a shell from its centre belongs to no cell of that side; giving
  // it to the faces of the cells next to it, as a one-dimensional tiling would, is right
  // for a shell that parallels the grid but leaves the cells along a tilted one open, and
  // a sheet sliding down a plate tilted 20° lost three times as much.)
  const double reach = std::sqrt(0.5) * dx;  // the square's farthest point
  for (int a = 0; a < 3; ++a) {
    if (empty()) break;
    const int t1 = (a + 1) % 3, t2 = (a + 2) % 3;
    const auto& closed = cell_face_hits(band)[a];
    apertures[a] = for_each_interior_band_face<FaceAperture>(
        band, a, [&](std::int64_t f, const Eigen::Vector3d& x) -> std::optional<FaceAperture> {
          const auto neumann = std::lower_bound(
              closed.begin(), closed.end(), f,
              [](const CellFaceHit& h, std::int64_t face) { return h.face < face; });
          if (neumann != closed.end() && neumann->face == f) return std::nullopt;  // Fig. 5
          const auto contact = nearest(x, reach, x);
          if (!contact || contact->on_open_edge) return std::nullopt;  // no plane beyond a hem
          // The §5.1 solve moves a rigid two-way body as one through the faces it cuts (its
          // velocity an unknown of the solve); β u + (1 − β) u_shell next to it would need
          // that unknown too. With it held at the body's velocity there, a floating boat was
          // pushed sideways (1.5 m in a second, Fig. 7 preview) and never filled.
          if (moves_as_one(contact->where.shell)) return std::nullopt;
          Eigen::Vector3d normal =
              m_shells[contact->where.shell]->mesh.scaled_normal(contact->where.triangle);
          if (!(normal.norm() > 0.0)) return std::nullopt;
          normal.normalize();
          const double offset = normal.dot(x - contact->point) / dx;
          if (offset < 0.0) normal = -normal;  // towards the centre's side
          const double fraction = open_square_fraction(normal[t1], normal[t2], std::abs(offset));
          if (std::abs(fraction - 1.0) <= 1e-9) return std::nullopt;
          return FaceAperture{f, fraction, contact->where};
        });
  }
  m_face_apertures = std::move(apertures);
  return *m_face_apertures;
}

Eigen::Vector3d ShellGeometry::velocity_at(const geometry::WedgeHit& hit) const {
  const Shell& shell = *m_shells[hit.shell];
  const auto& tri = *shell.triangles;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int c = 0; c < 3; ++c)
    v += hit.barycentric[c] * shell.velocities.row(tri(hit.triangle, c)).transpose();
  return v;
}

std::optional<Eigen::Vector3d> ShellGeometry::point_at(const geometry::WedgeHit& hit) const {
  if (hit.shell < 0 || hit.shell >= shell_count()) return std::nullopt;
  const geometry::TriangleMesh& mesh = m_shells[hit.shell]->mesh;
  if (hit.triangle < 0 || hit.triangle >= mesh.triangle_count()) return std::nullopt;
  const geometry::TriangleCorners c = mesh.corners(hit.triangle);
  return hit.barycentric[0] * c[0] + hit.barycentric[1] * c[1] + hit.barycentric[2] * c[2];
}

double ShellGeometry::surface_density_at(const geometry::WedgeHit& hit) const {
  const auto& sigma = m_shells[hit.shell]->surface_density;
  if (sigma.size() == 0) return 0.0;
  return sigma.size() == 1 ? sigma[0] : sigma[hit.triangle];
}

Eigen::Vector3d ShellGeometry::object_velocity(const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b) const {
  if (m_shells.empty()) return Eigen::Vector3d::Zero();
  if (const auto hit = m_caster->first_hit(a, b)) return velocity_at(*hit);
  // Fallback: the closest surface point to b over all shells.
  geometry::WedgeHit best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int s = 0; s < shell_count(); ++s) {
    const auto p = m_shells[s]->bvh.closest_point(b);
    if (p.triangle >= 0 && p.distance2 < best_d2) {
      best_d2 = p.distance2;
      best.shell = s;
      best.triangle = p.triangle;
      best.barycentric = p.barycentric;
    }
  }
  return best.shell >= 0 ? velocity_at(best) : Eigen::Vector3d::Zero();
}

bool ShellGeometry::on_open_edge(int s, int t, const Eigen::Vector3d& barycentric) const {
  const Shell& shell = *m_shells[s];
  std::call_once(shell.open_once, [&shell] {
    const sdk::Triangles& tri = *shell.triangles;
    const geometry::MeshEdges edges(tri);
    shell.open_edges.assign(static_cast<size_t>(tri.rows()), 0);
    shell.open_nodes.assign(static_cast<size_t>(shell.positions.rows()), 0);
    for (Eigen::Index t = 0; t < tri.rows(); ++t)
      for (int k = 0; k < 3; ++k) {  // edge k joins corners k, k + 1: opposite corner k + 2
        if (!edges.open(edges.triangle_edges[t][k])) continue;
        shell.open_edges[t] |= std::uint8_t(1u << ((k + 2) % 3));
        shell.open_nodes[tri(t, k)] = shell.open_nodes[tri(t, (k + 1) % 3)] = 1;
      }
  });
  // Ericson's closest point gives exact zeros off the face's interior.
  int zeros = 0, corner = 0, opposite = 0;
  for (int k = 0; k < 3; ++k) {
    if (barycentric[k] == 0.0) {
      ++zeros;
      opposite = k;
    } else {
      corner = k;
    }
  }
  if (zeros == 0) return false;
  if (zeros == 1) return (shell.open_edges[t] >> opposite & 1u) != 0;
  return shell.open_nodes[(*shell.triangles)(t, corner)] != 0;  // on a node
}

std::optional<ShellContact> ShellGeometry::nearest(const Eigen::Vector3d& p, double reach,
                                                  const Eigen::Vector3d& side) const {
  geometry::WedgeHit best;
  geometry::SurfacePoint closest;
  closest.distance2 = reach * reach;
  for (int s = 0; s < shell_count(); ++s) {
    const auto q = m_shells[s]->bvh.closest_point(p, std::sqrt(closest.distance2));
    if (q.triangle >= 0 && q.distance2 <= closest.distance2) {
      closest = q;
      best.shell = s;
      best.triangle = q.triangle;
      best.barycentric = q.barycentric;
    }
  }
  if (best.shell < 0) return std::nullopt;
  ShellContact c;
  c.distance = std::sqrt(closest.distance2);
  c.point = closest.point;
  c.velocity = velocity_at(best);
  c.on_open_edge = on_open_edge(best.shell, best.triangle, best.barycentric);
  c.where = best;
  // The distance gradient, unless p is on the surface to round-off (1e-9 of the reach).
  if (c.distance > 1e-9 * reach) {
    c.normal = (p - c.point) / c.distance;
  } else {
    const Eigen::Vector3d n = m_shells[best.shell]->mesh.scaled_normal(best.triangle);
    if (n.norm() == 0.0) return std::nullopt;  // a degenerate triangle: no side to push to
    c.normal = n.normalized();
    if (c.normal.dot(side - c.point) < 0.0) c.normal = -c.normal;
  }
  return c;
}

Eigen::Vector3d ShellGeometry::clip(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    double epsilon) const {
  if (m_shells.empty() || !m_caster->blocked(a, b, epsilon)) return b;
  if (m_caster->inside(a, epsilon)) return a;
  double lo = 0.0;
  double hi = 1.0;
  for (int it = 0; it < 10; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (m_caster->blocked(a, a + mid * (b - a), epsilon)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return a + lo * (b - a);
}

std::uint8_t ShellGeometry::hidden_axis_neighbours(const grid::UniformGrid& grid,
                                                   const Eigen::Vector3i& ijk) const {
  const Eigen::Vector3i n = grid.counts(grid::Location::Node);
  const Eigen::Vector3d x = grid.position(grid::Location::Node, ijk);
  std::uint8_t bits = 0;
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      Eigen::Vector3i nb = ijk;
      nb[a] += side == 0 ? -1 : 1;
      if (nb[a] < 0 || nb[a] >= n[a]) continue;
      if (!visible(x, grid.position(grid::Location::Node, nb)))
        bits |= std::uint8_t(1u << (2 * a + side));
    }
  return bits;
}

}  // namespace shellflow::grid_fluid
