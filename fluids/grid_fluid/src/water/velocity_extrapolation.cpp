#include "shellflow/grid_fluid/water/velocity_extrapolation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/geometry/gauss_jacobi_refill.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

ExtrapolationStats VelocityExtrapolation::extrapolate(
    MacGrid& mac, const std::array<std::vector<std::uint8_t>, 3>& known, const LevelSet& level_set,
    double width, const ShellGeometry& shells, const geometry::ShellBand* band) {
  ExtrapolationStats stats;
  const auto& phi = level_set.phi();
  const Eigen::Vector3i cells = m_grid.cells();
  for (int a = 0; a < 3; ++a) {
    const Location loc = face_location(a);
    const Eigen::Vector3i n = m_grid.counts(loc);
    const std::int64_t count = m_grid.size(loc);
    const std::int64_t stride[3] = {1, n.x(), std::int64_t(n.x()) * n.y()};
    const std::span<const std::uint8_t> in_band =
        band && !shells.empty() ? band->flags(loc) : std::span<const std::uint8_t>();
    auto& u = mac.face_velocity(a);
    m_face_phi.resize(count);
    m_valid.resize(count);
    std::int64_t known_count = 0;
#pragma omp parallel for schedule(static) reduction(+ : known_count)
    for (std::int64_t f = 0; f < count; ++f) {
      const Eigen::Vector3i ijk = m_grid.coordinates(loc, f);
      // The mean of its two cells; a domain face's, its one cell's (constant continuation).
      Eigen::Vector3i lower = ijk, upper = ijk;
      lower[a] = std::max(ijk[a] - 1, 0);
      upper[a] = std::min(ijk[a], cells[a] - 1);
      m_face_phi[f] = 0.5 * (phi[m_grid.index(Location::Cell, lower)] +
                             phi[m_grid.index(Location::Cell, upper)]);
      m_valid[f] = known[a][f] != 0 ? 1 : 0;
      known_count += known[a][f] != 0 ? 1 : 0;
    }
    stats.known_faces += known_count;
    m_order.clear();
    for (std::int64_t f = 0; f < count; ++f) {
      if (m_valid[f] != 0) continue;
      if (m_face_phi[f] < width) {
        m_order.push_back({m_face_phi[f], f});
      } else {
        u[f] = 0.0;  // beyond the band: never read
      }
    }
    std::sort(m_order.begin(), m_order.end());
    const auto visible = [&](std::int64_t from, std::int64_t to) {
      if (in_band.empty() || (in_band[from] == 0 && in_band[to] == 0)) return true;
      return shells.visible(m_grid.position(loc, from), m_grid.position(loc, to));
    };
    // The discrete ∇φ·∇u at a face the projection set (1 in `known`; a Neumann face holds
    // the shell's or wall's velocity, no slope), with the marching's own upwind stencil:
    // Σ_a (φ_f − φ_a)(u_f − u_a)/Δx² over its lower liquid neighbours, one per axis.
    const double dx = m_grid.dx(), dx2 = dx * dx;
    // Calls visit(g) for f's neighbours along axis ax in the grid that pass `take` (checked
    // first: it is cheap) and that f sees (a ray cast next to a shell).
    const auto for_each_seen_neighbour = [&](std::int64_t f, const Eigen::Vector3i& ijk, int ax,
                                             auto&& take, auto&& visit) {
      for (int side = 0; side < 2; ++side) {
        const int cc = ijk[ax] + (side == 0 ? -1 : 1);
        if (cc < 0 || cc >= n[ax]) continue;
        const std::int64_t g = f + (side == 0 ? -stride[ax] : stride[ax]);
        if (take(g) && visible(f, g)) visit(g);
      }
    };
    const auto normal_slope = [&](std::int64_t g) {
      if (known[a][g] != 1) return 0.0;
      const Eigen::Vector3i gijk = m_grid.coordinates(loc, g);
      double slope = 0.0;
      for (int ax = 0; ax < 3; ++ax) {
        std::int64_t best = -1;
        double best_phi = m_face_phi[g];
        const auto liquid_below = [&](std::int64_t h) {
          return known[a][h] == 1 && m_face_phi[h] < best_phi;
        };
        for_each_seen_neighbour(g, gijk, ax, liquid_below, [&](std::int64_t h) {
          best_phi = m_face_phi[h];
          best = h;
        });
        if (best >= 0) slope += (m_face_phi[g] - best_phi) * (u[g] - u[best]) / dx2;
      }
      return slope;
    };
    m_slope.clear();
    std::vector<std::int64_t> invalid;
    // Sequential in φ order: each face reads only faces of lower φ, already final.
    for (const auto& [phi_f, f] : m_order) {
      const Eigen::Vector3i ijk = m_grid.coordinates(loc, f);
      double weighted = 0.0, weights = 0.0, plain = 0.0, slope_weighted = 0.0;
      const bool linear = m_linear && phi_f < dx;
      int terms = 0;
      for (int ax = 0; ax < 3; ++ax) {
        std::int64_t best = -1;
        double best_phi = phi_f;
        const auto valid = [&](std::int64_t g) { return m_valid[g] != 0; };
        for_each_seen_neighbour(f, ijk, ax, valid, [&](std::int64_t g) {
          plain += u[g];
          ++terms;
          if (m_face_phi[g] < best_phi) {
            best_phi = m_face_phi[g];
            best = g;
          }
        });
        if (best >= 0) {
          weighted += (phi_f - best_phi) * u[best];
          weights += phi_f - best_phi;
          if (linear) {
            auto [known_slope, fresh] = m_slope.try_emplace(best, 0.0);
            if (fresh) known_slope->second = normal_slope(best);
            slope_weighted += (phi_f - best_phi) * known_slope->second;
          }
        }
      }
      if (weights > 0.0) {
        u[f] = weighted / weights;
        if (linear) {
          // Within a cell of the surface the normal slope d carries on (Aslam 2004's
          // linear extrapolation: ∇φ·∇u = d, d itself extrapolated constant), so with
          // the same weights u_f = (Σ w u_a + d Δx²)/Σ w. Constant extrapolation moved a
          // surface a fraction s of a cell above the last liquid face with that face's
          // velocity, an error k s Δx of a wave's speed. Beyond the first cell, constant.
          const double slope = slope_weighted / weights;
          m_slope[f] = slope;
          // Σw ≈ Δx Σ|n_a| >= Δx for a distance; below Δx/2 φ is too flat about the face
          // for d Δx²/Σw to mean a distance along the normal.
          if (weights >= 0.5 * dx) u[f] += slope * dx2 / weights;
        }
      } else if (terms > 0) {
        u[f] = plain / terms;  // level φ (a flat surface along this face): the mean
      } else {
        invalid.push_back(f);
        continue;
      }
      m_valid[f] = 1;
    }
    stats.extrapolated_faces += static_cast<std::int64_t>(m_order.size() - invalid.size());
    stats.invalid_faces += static_cast<std::int64_t>(invalid.size());
    if (!invalid.empty()) {
      // §3: hidden behind a shell from every known face: Gauss–Jacobi, object velocity.
      const geometry::GaussJacobiRefill refill(m_grid, loc);
      const auto object_value = [&](std::int64_t from, std::int64_t to) {
        return shells.object_velocity(m_grid.position(loc, from), m_grid.position(loc, to))[a];
      };
      refill.run(std::span<double>(u), std::span<std::uint8_t>(m_valid), invalid, visible,
                 object_value);
    }
  }
  return stats;
}

}  // namespace shellflow::grid_fluid
