#include "shellflow/grid_fluid/smoke/smoke_forces.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::grid_fluid {

using grid::Location;

double SmokeForces::add_buoyancy(NodeFields& fields, double dt, const BuoyancyParameters& p,
                                 bool temperature) const {
  const std::int64_t n = fields.size();
  const double beta = temperature && fields.has_temperature() ? p.temperature_beta : 0.0;
  const Eigen::Vector3d up = p.up.normalized();
  double fmax = 0.0;
  auto& rho = fields.density();
  auto& T = fields.temperature();
#pragma omp parallel for reduction(max : fmax)
  for (std::int64_t i = 0; i < n; ++i) {
    const double f =
        -p.density_alpha * rho[i] + (beta != 0.0 ? beta * (T[i] - p.ambient_temperature) : 0.0);
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
  // Only interior nodes are written and read (all six neighbours in the grid), but the
  // gradient of |ω| reads the boundary nodes' |ω| as 0: no full-grid fill each step.
  for (auto& w : m_omega) w.resize(count);
  if (static_cast<std::int64_t>(m_magnitude.size()) != count) m_magnitude.assign(count, 0.0f);
  const bool rays = band != nullptr && !shells.empty();
  if (rays) {
    m_visible_mask.assign(count, 0x3F);
    const auto list = band->samples(Location::Node);
    const std::int64_t m = static_cast<std::int64_t>(list.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t s = 0; s < m; ++s) {
      const std::int64_t i = list[s];
      m_visible_mask[i] = std::uint8_t(
          ~shells.hidden_axis_neighbours(m_grid, m_grid.coordinates(Location::Node, i)) & 0x3F);
    }
  }
  const std::uint8_t* mask = rays ? m_visible_mask.data() : nullptr;
  double* u[3] = {fields.velocity(0).data(), fields.velocity(1).data(), fields.velocity(2).data()};
  const double inv_2dx = 1.0 / (2.0 * dx);
  // ω = ∇ × u with hidden neighbours replaced by the object velocity (§4.1), row by row;
  // nodes that see all six neighbours (all of them without shells) take the plain
  // differences, written out so that the row vectorises.
  float* omega[3] = {m_omega[0].data(), m_omega[1].data(), m_omega[2].data()};
  float* magnitude = m_magnitude.data();
  const std::int64_t sy = stride[1], sz = stride[2];
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 1; k < n.z() - 1; ++k)
    for (int j = 1; j < n.y() - 1; ++j) {
      const std::int64_t row = sy * j + sz * k;
      const std::int64_t first = row + 1, last = row + n.x() - 1;
      for (std::int64_t i = first; i < last; ++i) {
        const double wx = ((u[2][i + sy] - u[2][i - sy]) - (u[1][i + sz] - u[1][i - sz])) * inv_2dx;
        const double wy = ((u[0][i + sz] - u[0][i - sz]) - (u[2][i + 1] - u[2][i - 1])) * inv_2dx;
        const double wz = ((u[1][i + 1] - u[1][i - 1]) - (u[0][i + sy] - u[0][i - sy])) * inv_2dx;
        omega[0][i] = static_cast<float>(wx);
        omega[1][i] = static_cast<float>(wy);
        omega[2][i] = static_cast<float>(wz);
        magnitude[i] = static_cast<float>(std::sqrt(wx * wx + wy * wy + wz * wz));
      }
      if (mask == nullptr) continue;
      for (std::int64_t i = first; i < last; ++i) {
        if (mask[i] == 0x3F) continue;
        Eigen::Vector3d v[3][2];
        for (int a = 0; a < 3; ++a)
          for (int side = 0; side < 2; ++side) {
            const std::int64_t nb = i + (side == 0 ? -stride[a] : stride[a]);
            v[a][side] = (mask[i] & (1u << (2 * a + side)))
                             ? fields.velocity_at(nb)
                             : shells.object_velocity(m_grid.position(Location::Node, i),
                                                      m_grid.position(Location::Node, nb));
          }
        const auto dv = [&](int comp, int axis) {
          return (v[axis][1][comp] - v[axis][0][comp]) * inv_2dx;
        };
        const Eigen::Vector3d w(dv(2, 1) - dv(1, 2), dv(0, 2) - dv(2, 0), dv(1, 0) - dv(0, 1));
        for (int a = 0; a < 3; ++a) omega[a][i] = static_cast<float>(w[a]);
        magnitude[i] = static_cast<float>(w.norm());
      }
    }
  // N = ∇|ω| / |∇|ω|| (hidden neighbours replaced by the centre value; the differences'
  // 1/(2Δx) cancels in N); f = ε Δx N × ω.
  double largest_squared = 0.0;
  const double scale = strength * dx;
#pragma omp parallel for collapse(2) schedule(static) reduction(max : largest_squared)
  for (int k = 1; k < n.z() - 1; ++k)
    for (int j = 1; j < n.y() - 1; ++j) {
      const std::int64_t row = sy * j + sz * k;
      for (std::int64_t i = row + 1; i < row + n.x() - 1; ++i) {
        double lo[3] = {magnitude[i - 1], magnitude[i - sy], magnitude[i - sz]};
        double hi[3] = {magnitude[i + 1], magnitude[i + sy], magnitude[i + sz]};
        if (mask != nullptr && mask[i] != 0x3F)
          for (int a = 0; a < 3; ++a) {
            if ((mask[i] & (1u << (2 * a))) == 0) lo[a] = magnitude[i];
            if ((mask[i] & (1u << (2 * a + 1))) == 0) hi[a] = magnitude[i];
          }
        const double gx = hi[0] - lo[0], gy = hi[1] - lo[1], gz = hi[2] - lo[2];
        const double g2 = gx * gx + gy * gy + gz * gz;
        const double s = g2 > 1e-300 ? scale / std::sqrt(g2) : 0.0;
        const double fx = s * (gy * omega[2][i] - gz * omega[1][i]);
        const double fy = s * (gz * omega[0][i] - gx * omega[2][i]);
        const double fz = s * (gx * omega[1][i] - gy * omega[0][i]);
        u[0][i] += dt * fx;
        u[1][i] += dt * fy;
        u[2][i] += dt * fz;
        largest_squared = std::max(largest_squared, fx * fx + fy * fy + fz * fz);
      }
    }
  return std::sqrt(largest_squared);
}

}  // namespace shellflow::grid_fluid
