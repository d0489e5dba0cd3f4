#include "shellflow/grid_fluid/smoke/smoke_forces.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::grid_fluid {

using grid::Location;

double SmokeForces::add_buoyancy(NodeFields& fields, double dt, const BuoyancyParameters& p,
                                 bool temperature) const {
  const std::int64_t n = fields.size();
  const double beta = temperature ? p.temperature_beta : 0.0;
  const Eigen::Vector3d up = p.up.normalized();
  double fmax = 0.0;
  auto& rho = fields.density();
  auto& T = fields.temperature();
#pragma omp parallel for reduction(max : fmax)
  for (std::int64_t i = 0; i < n; ++i) {
    const double f = -p.density_alpha * rho[i] + beta * (T[i] - p.ambient_temperature);
    if (f == 0.0) continue;
    for (int a = 0; a < 3; ++a) fields.velocity(a)[i] += dt * f * up[a];
    fmax = std::max(fmax, std::abs(f));
  }
  return fmax;
}

double SmokeForces::add_vorticity_confinement(NodeFields& fields, double dt, double strength,
                                              const ShellGeometry& shells,
                                              const geometry::ShellBand* band) {
  if (strength <= 0.0) return 0.0;
  const std::int64_t count = m_grid.size(Location::Node);
  const Eigen::Vector3i n = m_grid.counts(Location::Node);
  const std::int64_t stride[3] = {1, n.x(), std::int64_t{n.x()} * n.y()};
  const double dx = m_grid.dx();
  for (auto& w : m_omega) w.assign(count, 0.0);
  m_magnitude.assign(count, 0.0);
  m_visible_mask.assign(count, 0x3F);
  const bool rays = band != nullptr && !shells.empty();
  if (rays) {
    const auto list = band->samples(Location::Node);
    const std::int64_t m = static_cast<std::int64_t>(list.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t s = 0; s < m; ++s) {
      const std::int64_t i = list[s];
      // Only interior nodes read the mask: all six neighbours lie in the grid there.
      m_visible_mask[i] = std::uint8_t(
          ~shells.hidden_axis_neighbours(m_grid, m_grid.coordinates(Location::Node, i)) & 0x3F);
    }
  }
  const auto interior = [&](const Eigen::Vector3i& ijk) {
    return (ijk.array() > 0).all() && (ijk.array() < n.array() - 1).all();
  };
  // ω = ∇ × u with hidden neighbours replaced by the object velocity (§4.1).
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t i = 0; i < count; ++i) {
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, i);
    if (!interior(ijk)) continue;
    Eigen::Vector3d u[3][2];
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        const std::int64_t j = i + (side == 0 ? -stride[a] : stride[a]);
        if (m_visible_mask[i] & (1u << (2 * a + side))) {
          u[a][side] = fields.velocity_at(j);
        } else {
          u[a][side] = shells.object_velocity(m_grid.position(Location::Node, i),
                                              m_grid.position(Location::Node, j));
        }
      }
    const auto d = [&](int comp, int axis) {
      return (u[axis][1][comp] - u[axis][0][comp]) / (2.0 * dx);
    };
    const Eigen::Vector3d w(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1));
    for (int a = 0; a < 3; ++a) m_omega[a][i] = w[a];
    m_magnitude[i] = w.norm();
  }
  // N = ∇|ω| / |∇|ω||, hidden neighbours replaced by the centre value; f = ε Δx N × ω.
  double fmax = 0.0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(max : fmax)
  for (std::int64_t i = 0; i < count; ++i) {
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, i);
    if (!interior(ijk)) continue;
    Eigen::Vector3d grad;
    for (int a = 0; a < 3; ++a) {
      double side_value[2];
      for (int side = 0; side < 2; ++side) {
        const std::int64_t j = i + (side == 0 ? -stride[a] : stride[a]);
        const bool vis = (m_visible_mask[i] & (1u << (2 * a + side))) != 0;
        side_value[side] = vis ? m_magnitude[j] : m_magnitude[i];
      }
      grad[a] = (side_value[1] - side_value[0]) / (2.0 * dx);
    }
    const double g = grad.norm();
    if (g < 1e-300) continue;
    const Eigen::Vector3d N = grad / g;
    const Eigen::Vector3d w(m_omega[0][i], m_omega[1][i], m_omega[2][i]);
    const Eigen::Vector3d f = strength * dx * N.cross(w);
    for (int a = 0; a < 3; ++a) fields.velocity(a)[i] += dt * f[a];
    fmax = std::max(fmax, f.norm());
  }
  return fmax;
}

}  // namespace shellflow::grid_fluid
