#include "shellflow/grid_fluid/water/boundary_phi.hpp"

#include <algorithm>

#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

void BoundaryPhi::update(const grid::UniformGrid& lattice, const MacGrid& mac,
                         const std::array<bool, 6>& ruled) {
  m_lattice = lattice;
  const grid::UniformGrid& grid = mac.grid();
  const Eigen::Vector3i n = grid.cells();
  for (int side = 0; side < 6; ++side) {
    m_any[side] = false;
    auto& inward = m_inward[side];
    if (!ruled[side]) {
      inward.clear();
      continue;
    }
    const int a = side / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const bool max_side = side % 2 == 1;
    const auto& u = mac.face_velocity(a);
    inward.assign(std::size_t(n[b]) * n[c], 0);
    Eigen::Vector3i face;
    face[a] = max_side ? n[a] : 0;
    for (face[c] = 0; face[c] < n[c]; ++face[c])
      for (face[b] = 0; face[b] < n[b]; ++face[b]) {
        const double outward = max_side ? u[grid.index(face_location(a), face)]
                                        : -u[grid.index(face_location(a), face)];
        if (outward < 0.0) {
          inward[face[b] + std::size_t(n[b]) * face[c]] = 1;
          m_any[side] = true;
        }
      }
  }
}

double BoundaryPhi::pulled_away(double phi_b, double distance, double dx) {
  return std::max(-0.5 * dx, phi_b) + distance;
}

double BoundaryPhi::sample(std::span<const double> phi, const Eigen::Vector3d& p, double& lo,
                           double& hi) const {
  const Eigen::Vector3d lower = m_lattice.origin(), upper = m_lattice.upper();
  const Eigen::Vector3i n = m_lattice.counts(Location::Node);
  const NodeStencil st = node_stencil(m_lattice, p);  // clamped: on the outer plane beyond it
  std::array<double, 8> value;
  for (int c = 0; c < 8; ++c) value[c] = phi[st.corner(m_lattice, c)];
  for (int a = 0; a < 3; ++a) {
    const bool above = p[a] > upper[a];
    if (!above && !(p[a] < lower[a])) continue;
    const int side = 2 * a + (above ? 1 : 0);
    if (!m_any[side]) continue;
    const double distance = above ? p[a] - upper[a] : lower[a] - p[a];
    const int plane = above ? n[a] - 1 : 0;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3i node = st.base + corner_step(corner);
      if (node[a] != plane) continue;  // the other plane's corners weigh nothing here
      if (pulls(side, node)) value[corner] = pulled_away(value[corner], distance, m_lattice.dx());
    }
  }
  double v = 0.0;
  lo = value[0];
  hi = value[0];
  for (int c = 0; c < 8; ++c) {
    v += st.weight(c) * value[c];
    lo = std::min(lo, value[c]);
    hi = std::max(hi, value[c]);
  }
  return v;
}

}  // namespace shellflow::grid_fluid
