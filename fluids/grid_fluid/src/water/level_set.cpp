#include "shellflow/grid_fluid/water/level_set.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/ordered_sum.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

grid::UniformGrid LevelSet::cell_centre_lattice(const grid::UniformGrid& mac) {
  if ((mac.cells().array() < 2).any())
    throw std::invalid_argument("LevelSet: cell-centred φ needs two cells along every axis");
  return grid::UniformGrid(mac.origin() + Eigen::Vector3d::Constant(0.5 * mac.dx()), mac.dx(),
                           mac.cells() - Eigen::Vector3i::Ones());
}

namespace {

/// Throws unless `lattice`'s nodes are `band`'s cell centres (φ's samples are its cells).
void require_cell_lattice(const geometry::ShellBand& band, const grid::UniformGrid& lattice) {
  if (lattice.counts(Location::Node) != band.grid().counts(Location::Cell))
    throw std::invalid_argument("LevelSet: a lattice that is not the band's cell centres");
}

}  // namespace

std::span<const std::uint8_t> LevelSet::band_flags(const geometry::ShellBand& band,
                                                   const grid::UniformGrid& lattice) {
  require_cell_lattice(band, lattice);
  return band.flags(Location::Cell);
}

std::span<const std::int64_t> LevelSet::band_samples(const geometry::ShellBand& band,
                                                     const grid::UniformGrid& lattice) {
  require_cell_lattice(band, lattice);
  return band.samples(Location::Cell);
}

LevelSet::LevelSet(const grid::UniformGrid& grid, double band)
    : m_mac(grid),
      m_grid(cell_centre_lattice(grid)),
      m_band(band),
      m_phi(m_grid.size(Location::Node), band) {}

double LevelSet::sample(const Eigen::Vector3d& p) const {
  const NodeStencil st = node_stencil(m_grid, p);
  double v = 0.0;
  for (int c = 0; c < 8; ++c) v += st.weight(c) * m_phi[st.corner(m_grid, c)];
  return v;
}

namespace {

/// H(−φ): the smeared Heaviside of width eps (Osher and Fedkiw 2002, eq. 7.1), 1 in water.
double water_fraction(double phi, double eps) {
  if (phi >= eps) return 0.0;
  if (phi <= -eps) return 1.0;
  const double x = -phi;
  return 0.5 + x / (2.0 * eps) + std::sin(std::numbers::pi * x / eps) / (2.0 * std::numbers::pi);
}

}  // namespace

namespace {

/// The fraction of a tetrahedron where the linear interpolant of its corner values is
/// below zero, exact. The cut is a corner tetrahedron (one or three corners wet) or a
/// prism (two), whose volume follows from where the surface crosses the edges.
double tetrahedron_water_fraction(const std::array<double, 4>& phi) {
  std::array<double, 4> wet{}, dry{};
  int n_wet = 0, n_dry = 0;
  // φ <= 0 is water, as everywhere else (an emitter's nodes on its surface are 0).
  for (const double v : phi) (v <= 0.0 ? wet[n_wet++] : dry[n_dry++]) = v;
  // The fraction of edge (w, d) from its wet end w to the surface; w <= 0 < d.
  const auto cut = [](double w, double d) { return w / (w - d); };
  switch (n_wet) {
    case 0:
      return 0.0;
    case 1:
      return cut(wet[0], dry[0]) * cut(wet[0], dry[1]) * cut(wet[0], dry[2]);
    case 2: {
      // Prism between the wet edge and the surface: three tetrahedra (barycentric
      // determinants) with s1, s2 on the edges from wet[0] and s3, s4 from wet[1].
      const double s1 = cut(wet[0], dry[0]), s2 = cut(wet[0], dry[1]);
      const double s3 = cut(wet[1], dry[0]), s4 = cut(wet[1], dry[1]);
      return s1 * s2 * (1.0 - s4) + s1 * s4 * (1.0 - s3) + s3 * s4;
    }
    case 3:
      return 1.0 - (1.0 - cut(wet[0], dry[0])) * (1.0 - cut(wet[1], dry[0])) *
                       (1.0 - cut(wet[2], dry[0]));
    default:
      return 1.0;
  }
}

/// The six tetrahedra of a cube about its diagonal from corner 0 to corner 7 (corner
/// c = i + 2j + 4k), one per order of the three axes: they tile the cube, 1/6 each.
constexpr std::array<std::array<int, 4>, 6> kCubeTetrahedra = {
    {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

/// A tetrahedron: its corners (in cell units) and a linear field's values there.
struct Tetrahedron {
  std::array<Eigen::Vector3d, 4> x;
  std::array<double, 4> phi;
};

double tetrahedron_volume(const Tetrahedron& t) {
  return std::abs((t.x[1] - t.x[0]).dot((t.x[2] - t.x[0]).cross(t.x[3] - t.x[0]))) / 6.0;
}

/// The volume of t where the linear field `side` (values at t's corners) is below zero,
/// and its φ below zero there: t cut by side's plane into tetrahedra (a corner one, or a
/// prism of three), each measured by tetrahedron_water_fraction.
double water_below_plane(const Tetrahedron& t, const std::array<double, 4>& side) {
  std::array<int, 4> in{}, out{};
  int n_in = 0, n_out = 0;
  for (int v = 0; v < 4; ++v) (side[v] < 0.0 ? in[n_in++] : out[n_out++]) = v;
  const auto water = [](const Tetrahedron& p) {
    return tetrahedron_volume(p) * tetrahedron_water_fraction(p.phi);
  };
  if (n_in == 0) return 0.0;
  if (n_in == 4) return water(t);
  // The point of edge (a, b) on the plane, with φ there.
  const auto on_plane = [&](int a, int b) {
    const double s = side[a] / (side[a] - side[b]);
    return std::pair{t.x[a] + s * (t.x[b] - t.x[a]), t.phi[a] + s * (t.phi[b] - t.phi[a])};
  };
  const auto tet = [](std::initializer_list<std::pair<Eigen::Vector3d, double>> v) {
    Tetrahedron r;
    int k = 0;
    for (const auto& [x, f] : v) r.x[k] = x, r.phi[k++] = f;
    return r;
  };
  const auto corner = [&](int v) { return std::pair{t.x[v], t.phi[v]}; };
  if (n_in == 1) {
    const int a = in[0];
    return water(tet({corner(a), on_plane(a, out[0]), on_plane(a, out[1]), on_plane(a, out[2])}));
  }
  if (n_in == 2) {
    const auto a = corner(in[0]), b = corner(in[1]);
    const auto ac = on_plane(in[0], out[0]), ad = on_plane(in[0], out[1]);
    const auto bc = on_plane(in[1], out[0]), bd = on_plane(in[1], out[1]);
    return water(tet({a, ac, ad, b})) + water(tet({ac, ad, b, bc})) + water(tet({ad, b, bc, bd}));
  }
  // Three in: the prism between their face and where their edges to the fourth cross.
  const int d = out[0];
  const auto a = corner(in[0]), b = corner(in[1]), c = corner(in[2]);
  const auto ad = on_plane(in[0], d), bd = on_plane(in[1], d), cd = on_plane(in[2], d);
  return water(tet({a, b, c, ad})) + water(tet({b, c, ad, bd})) + water(tet({c, ad, bd, cd}));
}

}  // namespace

double LevelSet::cell_fraction(const std::array<double, 8>& corner) {
  bool any_wet = false, any_dry = false;
  for (const double v : corner) (v < 0.0 ? any_wet : any_dry) = true;
  if (!any_dry) return 1.0;
  if (!any_wet) return 0.0;
  double sum = 0.0;
  for (const auto& t : kCubeTetrahedra)
    sum += tetrahedron_water_fraction({corner[t[0]], corner[t[1]], corner[t[2]], corner[t[3]]});
  return sum / 6.0;
}

double LevelSet::two_sided_cell_fraction(const std::array<double, 8>& phi_below,
                                         const std::array<double, 8>& phi_above,
                                         const std::array<double, 8>& side) {
  double sum = 0.0;
  for (const auto& k : kCubeTetrahedra) {
    Tetrahedron below, above;
    std::array<double, 4> s, minus_s;
    for (int v = 0; v < 4; ++v) {
      const int c = k[v];
      const Eigen::Vector3d x = corner_step(c).cast<double>();
      below.x[v] = above.x[v] = x;
      below.phi[v] = phi_below[c];
      above.phi[v] = phi_above[c];
      s[v] = side[c];
      minus_s[v] = -side[c];
    }
    sum += water_below_plane(below, s) + water_below_plane(above, minus_s);
  }
  return sum;
}

double LevelSet::volume() const {
  const Eigen::Vector3i n = m_mac.cells();
  return volume({Eigen::Vector3i::Zero(), n - Eigen::Vector3i::Ones()});
}

double LevelSet::volume(const grid::IndexBox& cells) const {
  if (cells.empty()) return 0.0;
  // Lattice cell d (d = 0..n per axis) lies between centres d − 1 and d, clamped at the
  // sides (constant continuation), and covers MAC-cell coordinates [d − ½, d + ½].
  const Eigen::Vector3i n = m_grid.counts(Location::Node);
  const auto overlap = [&](int a, int d) {
    return std::max(0.0, std::min(d + 0.5, cells.hi[a] + 1.0) - std::max(d - 0.5, 1.0 * cells.lo[a]));
  };
  const int first_y = cells.lo.y(), rows_y = cells.hi.y() - cells.lo.y() + 2;
  const std::int64_t rows = std::int64_t(rows_y) * (cells.hi.z() - cells.lo.z() + 2);
  const double sum = ordered_sum(rows, [&](std::int64_t r) {
    const int j = first_y + int(r % rows_y), k = cells.lo.z() + int(r / rows_y);
    const double w_jk = overlap(1, j) * overlap(2, k);
    if (w_jk == 0.0) return 0.0;
    const int y[2] = {std::max(j - 1, 0), std::min(j, n.y() - 1)};
    const int z[2] = {std::max(k - 1, 0), std::min(k, n.z() - 1)};
    double row = 0.0;
    for (int i = cells.lo.x(); i <= cells.hi.x() + 1; ++i) {
      const double w = overlap(0, i);
      if (w == 0.0) continue;
      const int x[2] = {std::max(i - 1, 0), std::min(i, n.x() - 1)};
      std::array<double, 8> corner;
      for (int c = 0; c < 8; ++c)
        corner[c] = m_phi[m_grid.index(Location::Node, x[c & 1], y[c >> 1 & 1], z[c >> 2])];
      row += w * cell_fraction(corner);
    }
    return w_jk * row;
  });
  const double dx = m_grid.dx();
  return sum * dx * dx * dx;
}

double LevelSet::symmetric_difference(const std::vector<double>& other) const {
  if (other.size() != m_phi.size())
    throw std::invalid_argument("LevelSet::symmetric_difference: another grid's φ");
  const double eps = 1.5 * m_grid.dx();
  const double sum = ordered_sum(static_cast<std::int64_t>(m_phi.size()), [&](std::int64_t node) {
    const double d = std::abs(water_fraction(m_phi[node], eps) - water_fraction(other[node], eps));
    return d;
  });
  const double dx = m_grid.dx();
  return sum * dx * dx * dx;
}

std::int64_t LevelSet::liquid_cells() const {
  std::int64_t count = 0;
  const std::int64_t n = static_cast<std::int64_t>(m_phi.size());
#pragma omp parallel for schedule(static) reduction(+ : count)
  for (std::int64_t i = 0; i < n; ++i) count += m_phi[i] <= 0.0 ? 1 : 0;
  return count;
}

}  // namespace shellflow::grid_fluid
