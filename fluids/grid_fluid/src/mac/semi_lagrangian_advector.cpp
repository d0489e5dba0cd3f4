#include "shellflow/grid_fluid/mac/semi_lagrangian_advector.hpp"

#include <algorithm>
#include <array>

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

/// Trilinear interpolation of the 8 corner values (corner c: bit 0 +x, bit 1 +y, bit 2 +z)
/// as nested linear interpolations, x then y then z. Both paths of advect() use it, so a
/// node gets the same bits whether or not it lies in the shell band.
inline double trilinear(const std::array<double, 8>& v, const Eigen::Vector3d& f) {
  const auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double y0 = lerp(lerp(v[0], v[1], f.x()), lerp(v[2], v[3], f.x()), f.y());
  const double y1 = lerp(lerp(v[4], v[5], f.x()), lerp(v[6], v[7], f.x()), f.y());
  return lerp(y0, y1, f.z());
}

}  // namespace

void SemiLagrangianAdvector::advect(const NodeFields& in, NodeFields& out, double dt,
                                    const ShellGeometry& shells, const geometry::ShellBand* band,
                                    std::span<const std::uint8_t> active) const {
  const std::span<const std::uint8_t> in_band =
      band && !shells.empty() ? band->flags(Location::Node) : std::span<const std::uint8_t>();
  const double eps_prime = geometry::WedgeCaster::kSemiLagrangianFactor * shells.epsilon();
  const Eigen::Vector3i cells = m_grid.cells();
  const Eigen::Vector3i nodes = m_grid.counts(Location::Node);
  const std::int64_t sy = nodes.x(), sz = std::int64_t(nodes.x()) * nodes.y();
  const std::array<std::int64_t, 8> corner_offset = node_corner_offsets(m_grid);
  const int fields = in.field_count();
  const double* field_in[5] = {in.velocity(0).data(), in.velocity(1).data(),
                               in.velocity(2).data(), in.density().data(),
                               in.temperature().data()};
  double* field_out[5] = {out.velocity(0).data(), out.velocity(1).data(),
                          out.velocity(2).data(), out.density().data(),
                          out.temperature().data()};
  const double steps = dt / m_grid.dx();  // grid cells per unit velocity

  // §4.1 in the shell band: clip the ray against the doubled wedges, then 8 secondary rays.
  const auto advect_near_shell = [&](std::int64_t node, const Eigen::Vector3d& departure_q) {
    const Eigen::Vector3d x = m_grid.position(Location::Node, node);
    const Eigen::Vector3d departure = m_grid.origin() + m_grid.dx() * departure_q;
    const Eigen::Vector3d base = shells.clip(x, departure, eps_prime);
    const NodeStencil st = node_stencil(m_grid, base);
    const std::int64_t first = st.corner(m_grid, 0);
    std::array<std::array<double, 8>, 5> corner{};
    for (int c = 0; c < 8; ++c) {
      const std::int64_t index = first + corner_offset[c];
      if (st.weight(c) == 0.0 || shells.visible(base, m_grid.position(Location::Node, index))) {
        for (int m = 0; m < fields; ++m) corner[m][c] = field_in[m][index];
      } else {
        const Eigen::Vector3d object =
            shells.object_velocity(base, m_grid.position(Location::Node, index));
        for (int a = 0; a < 3; ++a) corner[a][c] = object[a];
        if (fields >= 4) corner[3][c] = 0.0;        // zero density behind a shell
        if (fields == 5) corner[4][c] = m_ambient;  // ambient temperature behind a shell
      }
    }
    for (int m = 0; m < fields; ++m) field_out[m][node] = trilinear(corner[m], st.fraction);
  };

#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < nodes.z(); ++k)
    for (int j = 0; j < nodes.y(); ++j) {
      const std::int64_t row = sy * j + sz * k;
      for (int i = 0; i < nodes.x(); ++i) {
        const std::int64_t node = row + i;
        if (!active.empty() && active[node] == 0) {
          for (int m = 0; m < fields; ++m) field_out[m][node] = field_in[m][node];
          continue;
        }
        const Eigen::Vector3d q(i - steps * field_in[0][node], j - steps * field_in[1][node],
                                k - steps * field_in[2][node]);
        if (!in_band.empty() && in_band[node] != 0) {
          advect_near_shell(node, q);
          continue;
        }
        // The departure point in cells (node_stencil's convention).
        const NodeStencil st = node_stencil_in_cells(cells, q);
        const std::int64_t first = st.base.x() + sy * st.base.y() + sz * st.base.z();
        for (int m = 0; m < fields; ++m) {
          const double* f = field_in[m] + first;
          const std::array<double, 8> v = {f[corner_offset[0]], f[corner_offset[1]],
                                           f[corner_offset[2]], f[corner_offset[3]],
                                           f[corner_offset[4]], f[corner_offset[5]],
                                           f[corner_offset[6]], f[corner_offset[7]]};
          field_out[m][node] = trilinear(v, st.fraction);
        }
      }
    }
}

}  // namespace shellflow::grid_fluid
