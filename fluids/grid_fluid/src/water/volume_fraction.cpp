#include "shellflow/grid_fluid/water/volume_fraction.hpp"

#include <algorithm>
#include <cmath>

#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/ordered_sum.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

/// F this close to 0 or 1 counts as empty or full: no plane is fitted to it.
constexpr double kEmpty = 1e-9;

}  // namespace

double VolumeFraction::box_fraction_below(const Eigen::Vector3d& normal, double d,
                                          const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  // A plane's signed distance is linear: the marching tetrahedra of LevelSet::cell_fraction
  // are exact for it, in a box of any proportions (an affine map keeps the fraction).
  std::array<double, 8> corner;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3i step = corner_step(c);
    const Eigen::Vector3d x(step.x() ? hi.x() : lo.x(), step.y() ? hi.y() : lo.y(),
                            step.z() ? hi.z() : lo.z());
    corner[c] = normal.dot(x) - d;
  }
  return LevelSet::cell_fraction(corner);
}

double VolumeFraction::plane_height(const Eigen::Vector3d& normal, double fraction) {
  const Eigen::Vector3d lo = Eigen::Vector3d::Constant(-0.5), hi = Eigen::Vector3d::Constant(0.5);
  // The fraction grows with d from 0 to 1 over [−reach, reach], smoothly (a cubic per
  // piece): regula falsi with the Illinois step keeps the root bracketed and converges
  // superlinearly, to 1e-13 of the cube in about ten evaluations.
  const double reach = 0.5 * normal.cwiseAbs().sum();
  double a = -reach, b = reach, fa = -fraction, fb = 1.0 - fraction;
  int side = 0;
  for (int n = 0; n < 100 && b - a > 1e-13; ++n) {
    const double c = (a * fb - b * fa) / (fb - fa);
    const double fc = box_fraction_below(normal, c, lo, hi) - fraction;
    if (fc == 0.0) return c;
    if ((fc < 0.0) == (fa < 0.0)) {
      a = c, fa = fc;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      b = c, fb = fc;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
    if (std::abs(fc) < 1e-15) return c;
  }
  return 0.5 * (a + b);
}

namespace {

/// The water fraction of the cell of `grid` centred at `centre` where `distance` is below
/// zero, from 4³ points (each a plane's share of its sub-cell, |∇d| = 1: exact for a
/// plane along the grid).
template <class Distance>
double sampled_fraction(const grid::UniformGrid& grid, const Eigen::Vector3d& centre,
                        const Distance& distance) {
  constexpr int kPoints = 4;
  const double dx = grid.dx(), h = dx / kPoints;
  const Eigen::Vector3d low = centre - Eigen::Vector3d::Constant(0.5 * dx);
  double water = 0.0;
  for (int k = 0; k < kPoints; ++k)
    for (int j = 0; j < kPoints; ++j)
      for (int i = 0; i < kPoints; ++i)
        water += std::clamp(
            0.5 - distance(Eigen::Vector3d(low + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5))) / h,
            0.0, 1.0);
  return water / (kPoints * kPoints * kPoints);
}

}  // namespace

VolumeFraction::VolumeFraction(const LevelSet& level_set) : m_mac(level_set.mac_grid()) {
  const std::int64_t count = m_mac.size(Location::Cell);
  m_fraction.assign(count, 0.0);
#pragma omp parallel for schedule(static)
  for (std::int64_t cell = 0; cell < count; ++cell)
    m_fraction[cell] = sampled_fraction(m_mac, m_mac.position(Location::Cell, cell),
                                        [&](const Eigen::Vector3d& q) { return level_set.sample(q); });
}

double VolumeFraction::fill(const std::function<double(const Eigen::Vector3d&)>& distance,
                            const grid::IndexBox& cells) {
  if (cells.empty()) return 0.0;
  double added = 0.0;
  for (int k = cells.lo.z(); k <= cells.hi.z(); ++k)
    for (int j = cells.lo.y(); j <= cells.hi.y(); ++j)
      for (int i = cells.lo.x(); i <= cells.hi.x(); ++i) {
        const std::int64_t c = m_mac.index(Location::Cell, i, j, k);
        const double shape =
            sampled_fraction(m_mac, m_mac.position(Location::Cell, c), distance);
        if (shape > m_fraction[c]) {
          added += shape - m_fraction[c];
          m_fraction[c] = shape;
        }
      }
  const double dx = m_mac.dx();
  return added * dx * dx * dx;
}

double VolumeFraction::volume() const {
  const double sum = ordered_sum(static_cast<std::int64_t>(m_fraction.size()),
                                 [&](std::int64_t c) { return m_fraction[c]; });
  const double dx = m_mac.dx();
  return sum * dx * dx * dx;
}

Eigen::Vector3d VolumeFraction::normal_at(const LevelSet& level_set, const Eigen::Vector3i& c) const {
  const Eigen::Vector3i n = m_mac.cells();
  const auto& phi = level_set.phi();
  const auto gradient = [&](const std::vector<double>& field) {
    Eigen::Vector3d g;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3i lo = c, hi = c;
      lo[a] = std::max(c[a] - 1, 0);
      hi[a] = std::min(c[a] + 1, n[a] - 1);
      g[a] = hi[a] == lo[a] ? 0.0
                            : (field[m_mac.index(Location::Cell, hi)] -
                               field[m_mac.index(Location::Cell, lo)]) /
                                  (hi[a] - lo[a]);
    }
    return g;
  };
  Eigen::Vector3d g = gradient(phi);
  if (g.norm() < 1e-12 * m_mac.dx()) g = -gradient(m_fraction);
  if (g.norm() == 0.0) return Eigen::Vector3d::UnitZ();
  return g.normalized();
}

void VolumeFraction::advect(const std::array<const std::vector<double>*, 3>& u,
                            const LevelSet& level_set, double dt, std::int64_t step) {
  m_stats = VolumeFractionStats{};
  // Weymouth and Yue's sweeps keep F in [0, 1] up to a Courant number of ½ per sweep: the
  // step is split to stay within it (the faces next to liquid cells carry the projection's
  // values, which may outrun the step's CFL speed where θ is small).
  double fastest = 0.0;
  for (int a = 0; a < 3; ++a)
    for (const double w : *u[a]) fastest = std::max(fastest, std::abs(w));
  const int parts = std::max(1, static_cast<int>(std::ceil(fastest * dt / m_mac.dx() / 0.5)));
  // The dilation term's cells: the liquid cells of φ^n, whose faces the projection made
  // divergence free, so that the terms add up to nothing (Weymouth and Yue take F > ½,
  // which φ^n's liquid cells are once correct() has moved φ to F).
  const auto& phi = level_set.phi();
  m_full.resize(phi.size());
  for (size_t c = 0; c < phi.size(); ++c) m_full[c] = phi[c] <= 0.0 ? 1 : 0;
  double clipped = 0.0, outflow = 0.0, dilated = 0.0;
  for (int part = 0; part < parts; ++part) {
    sweep(u, level_set, dt / parts, step * 3 + part);
    clipped += m_stats.clipped;
    outflow += m_stats.outflow;
    dilated += m_stats.dilated;
  }
  m_stats.clipped = clipped;
  m_stats.outflow = outflow;
  m_stats.dilated = dilated;
}

void VolumeFraction::sweep(const std::array<const std::vector<double>*, 3>& u,
                           const LevelSet& level_set, double dt, std::int64_t step) {
  const Eigen::Vector3i n = m_mac.cells();
  const std::int64_t count = m_mac.size(Location::Cell);
  const double dx = m_mac.dx();
  // The planes' normals from φ^n, once for the step's mixed cells.
  std::vector<Eigen::Vector3d> normal(count, Eigen::Vector3d::Zero());
#pragma omp parallel for schedule(static)
  for (std::int64_t c = 0; c < count; ++c)
    if (m_fraction[c] > kEmpty && m_fraction[c] < 1.0 - kEmpty)
      normal[c] = normal_at(level_set, m_mac.coordinates(Location::Cell, c));
  double clipped = 0.0, outflow = 0.0, dilated = 0.0;
  for (int sweep = 0; sweep < 3; ++sweep) {
    const int a = step % 2 == 0 ? sweep : 2 - sweep;
    const auto& w = *u[a];
    const Location loc = face_location(a);
    // Each mixed cell's plane height for this sweep's F.
    std::vector<double> height(count, 0.0);
#pragma omp parallel for schedule(static)
    for (std::int64_t c = 0; c < count; ++c)
      if (!normal[c].isZero() && m_fraction[c] > kEmpty && m_fraction[c] < 1.0 - kEmpty)
        height[c] = plane_height(normal[c], m_fraction[c]);
    // The water each face carries this sweep [cell volumes], + along the axis.
    std::vector<double> carried(m_mac.size(loc), 0.0);
#pragma omp parallel for schedule(static)
    for (std::int64_t f = 0; f < m_mac.size(loc); ++f) {
      const Eigen::Vector3i ijk = m_mac.coordinates(loc, f);
      // A side's face carries water out where it is open and its flow leaves; none comes in.
      if (ijk[a] == 0 && !(m_open[2 * a] && w[f] < 0.0)) continue;
      if (ijk[a] == n[a] && !(m_open[2 * a + 1] && w[f] > 0.0)) continue;
      const double s = std::min(std::abs(w[f]) * dt / dx, 1.0);
      if (s == 0.0) continue;
      Eigen::Vector3i donor = ijk;
      if (w[f] > 0.0) donor[a] -= 1;
      const std::int64_t d = m_mac.index(Location::Cell, donor);
      const double fraction = m_fraction[d];
      double water;
      if (fraction <= kEmpty) {
        water = 0.0;
      } else if (fraction >= 1.0 - kEmpty || normal[d].isZero()) {
        water = s * fraction;
      } else {
        // The donor's slab next to the face, below its plane.
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(-0.5), hi = Eigen::Vector3d::Constant(0.5);
        if (w[f] > 0.0)
          lo[a] = 0.5 - s;
        else
          hi[a] = -0.5 + s;
        water = s * box_fraction_below(normal[d], height[d], lo, hi);
      }
      carried[f] = w[f] > 0.0 ? water : -water;
    }
    for (int side = 0; side < 2; ++side) {
      if (!m_open[2 * a + side]) continue;
      const double sign = side == 0 ? -1.0 : 1.0;  // carried is + along the axis
      outflow += ordered_sum(m_mac.size(loc), [&](std::int64_t f) {
        const int along = m_mac.coordinates(loc, f)[a];
        return along == (side == 0 ? 0 : n[a]) ? sign * carried[f] : 0.0;
      });
    }
    // F − (out − in) + c (u⁺ − u⁻) dt/Δx (Weymouth and Yue 2010, eq. 9).
#pragma omp parallel for schedule(static) reduction(+ : clipped, dilated)
    for (std::int64_t c = 0; c < count; ++c) {
      const Eigen::Vector3i ijk = m_mac.coordinates(Location::Cell, c);
      Eigen::Vector3i upper = ijk;
      upper[a] += 1;
      const std::int64_t f_lo = m_mac.index(loc, ijk), f_hi = m_mac.index(loc, upper);
      double value = m_fraction[c] + carried[f_lo] - carried[f_hi];
      if (m_full[c] != 0) {
        const double dilation = (w[f_hi] - w[f_lo]) * dt / dx;
        value += dilation;
        dilated += dilation;
      }
      // Where the air's extrapolated faces converge a cell may take in more than it holds:
      // the excess stays in it (carried on with the flux of a full cell) rather than being
      // lost. Below zero there is nothing to carry.
      const double kept = std::max(value, 0.0);
      clipped += kept - value;
      m_fraction[c] = kept;
    }
  }
  m_stats.clipped = clipped * dx * dx * dx;
  m_stats.outflow = outflow * dx * dx * dx;
  m_stats.dilated = dilated * dx * dx * dx;
}

void VolumeFraction::correct(LevelSet& level_set, bool signs_only) {
  auto& phi = level_set.phi();
  const double dx = m_mac.dx();
  const std::int64_t count = m_mac.size(Location::Cell);
  std::vector<double> corrected(phi);
  std::int64_t moved = 0, mixed = 0;
#pragma omp parallel for schedule(static) reduction(+ : moved, mixed)
  for (std::int64_t c = 0; c < count; ++c) {
    const double fraction = m_fraction[c];
    if (fraction <= kEmpty) {
      if (phi[c] <= 0.0) corrected[c] = 0.5 * dx, ++moved;  // F holds none: air
      continue;
    }
    if (fraction >= 1.0 - kEmpty) {
      if (phi[c] > 0.0) corrected[c] = -0.5 * dx, ++moved;  // F fills it: water
      continue;
    }
    ++mixed;
    if (signs_only && (phi[c] <= 0.0) == (fraction >= 0.5)) continue;
    // The centre's signed distance to F's plane (the plane n·x = d, x about the centre).
    const Eigen::Vector3d normal = normal_at(level_set, m_mac.coordinates(Location::Cell, c));
    corrected[c] = -plane_height(normal, fraction) * dx;
    ++moved;
  }
  phi.swap(corrected);
  const double excess = ordered_sum(count, [&](std::int64_t c) { return std::max(m_fraction[c] - 1.0, 0.0); });
  m_stats.excess = excess * dx * dx * dx;
  m_stats.mixed_cells = mixed;
  m_stats.moved_cells += moved;
}

}  // namespace shellflow::grid_fluid
