#include "shellflow/grid_fluid/mac/semi_lagrangian_advector.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

void SemiLagrangianAdvector::advect(const NodeFields& in, NodeFields& out, double dt,
                                    const ShellGeometry& shells, const geometry::ShellBand* band,
                                    std::span<const std::uint8_t> active) const {
  const std::int64_t count = m_grid.size(Location::Node);
  const std::span<const std::uint8_t> in_band =
      band && !shells.empty() ? band->flags(Location::Node) : std::span<const std::uint8_t>();
  const Eigen::Vector3d lower = m_grid.origin();
  const Eigen::Vector3d upper = m_grid.upper();
  const double eps_prime = geometry::WedgeCaster::kSemiLagrangianFactor * shells.epsilon();
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t node = 0; node < count; ++node) {
    if (!active.empty() && active[node] == 0) {
      out.set(node, in.sample(node));
      continue;
    }
    const Eigen::Vector3d x = m_grid.position(Location::Node, node);
    const Eigen::Vector3d departure =
        (x - dt * in.velocity_at(node)).cwiseMax(lower).cwiseMin(upper);
    NodeSample value = NodeSample::Zero();
    if (in_band.empty() || in_band[node] == 0) {
      const NodeStencil st = node_stencil(m_grid, departure);
      for (int c = 0; c < 8; ++c) value += st.weight(c) * in.sample(st.corner(m_grid, c));
    } else {
      // §4.1: clip the ray against the doubled wedges, then 8 secondary rays.
      const Eigen::Vector3d base = shells.clip(x, departure, eps_prime);
      const NodeStencil st = node_stencil(m_grid, base);
      for (int c = 0; c < 8; ++c) {
        const double w = st.weight(c);
        if (w == 0.0) continue;
        const std::int64_t corner = st.corner(m_grid, c);
        const Eigen::Vector3d y = m_grid.position(Location::Node, corner);
        if (shells.visible(base, y)) {
          value += w * in.sample(corner);
        } else {
          NodeSample object;
          object.head<3>() = shells.object_velocity(base, y);
          object[3] = 0.0;        // zero density behind a shell
          object[4] = m_ambient;  // ambient temperature behind a shell
          value += w * object;
        }
      }
    }
    out.set(node, value);
  }
}

}  // namespace shellflow::grid_fluid
