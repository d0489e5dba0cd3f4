#include "shellflow/grid_fluid/mac/semi_lagrangian_advector.hpp"

#include <algorithm>
#include <array>

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

/// Trilinear interpolation of the 8 corner values (corner c: bit 0 +x, bit 1 +y, bit 2 +z)
/// as nested linear interpolations, x then y then z. Both paths of advect() use it, so a
/// node gets the same bits whether or not it lies in the shell band.
inline double trilinear(const std::array<double, 8>& v, double fx, double fy, double fz) {
  const auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double y0 = lerp(lerp(v[0], v[1], fx), lerp(v[2], v[3], fx), fy);
  const double y1 = lerp(lerp(v[4], v[5], fx), lerp(v[6], v[7], fx), fy);
  return lerp(y0, y1, fz);
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
  const std::int64_t corner_offset[8] = {0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1};
  const int fields = in.has_smoke() ? 5 : 3;
  const double* field_in[5] = {in.velocity(0).data(), in.velocity(1).data(),
                               in.velocity(2).data(), in.density().data(),
                               in.temperature().data()};
  double* field_out[5] = {out.velocity(0).data(), out.velocity(1).data(),
                          out.velocity(2).data(), out.density().data(),
                          out.temperature().data()};
  const double steps = dt / m_grid.dx();  // grid cells per unit velocity

  // The departure point of node (i, j, k) in grid units, clamped into the box, as the
  // lower corner of its cell and the fractions in it (node_stencil's convention: a point
  // on the upper face lies in the last cell at fraction 1).
  struct Stencil {
    std::int64_t base;
    double f[3];
  };
  const auto stencil_at = [&](const Eigen::Vector3d& q_unclamped) {
    Stencil s;
    int ijk[3];
    for (int a = 0; a < 3; ++a) {
      const double q = std::clamp(q_unclamped[a], 0.0, static_cast<double>(cells[a]));
      ijk[a] = std::min(static_cast<int>(q), cells[a] - 1);  // q >= 0: truncation is floor
      s.f[a] = q - ijk[a];
    }
    s.base = ijk[0] + sy * ijk[1] + sz * ijk[2];
    return s;
  };
  // §4.1 in the shell band: clip the ray against the doubled wedges, then 8 secondary rays.
  const auto advect_near_shell = [&](std::int64_t node, const Eigen::Vector3d& departure_q) {
    const Eigen::Vector3d x = m_grid.position(Location::Node, node);
    const Eigen::Vector3d departure = m_grid.origin() + m_grid.dx() * departure_q;
    const Eigen::Vector3d base = shells.clip(x, departure, eps_prime);
    const Stencil st = stencil_at((base - m_grid.origin()) / m_grid.dx());
    std::array<std::array<double, 8>, 5> corner{};
    for (int c = 0; c < 8; ++c) {
      const std::int64_t index = st.base + corner_offset[c];
      const double w = ((c & 1) ? st.f[0] : 1.0 - st.f[0]) *
                       ((c >> 1 & 1) ? st.f[1] : 1.0 - st.f[1]) *
                       ((c >> 2) ? st.f[2] : 1.0 - st.f[2]);
      if (w == 0.0 || shells.visible(base, m_grid.position(Location::Node, index))) {
        for (int m = 0; m < fields; ++m) corner[m][c] = field_in[m][index];
      } else {
        const Eigen::Vector3d object =
            shells.object_velocity(base, m_grid.position(Location::Node, index));
        for (int a = 0; a < 3; ++a) corner[a][c] = object[a];
        if (fields == 5) {
          corner[3][c] = 0.0;        // zero density behind a shell
          corner[4][c] = m_ambient;  // ambient temperature behind a shell
        }
      }
    }
    for (int m = 0; m < fields; ++m)
      field_out[m][node] = trilinear(corner[m], st.f[0], st.f[1], st.f[2]);
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
        const Stencil st = stencil_at(q);
        for (int m = 0; m < fields; ++m) {
          const double* f = field_in[m] + st.base;
          const std::array<double, 8> v = {f[corner_offset[0]], f[corner_offset[1]],
                                           f[corner_offset[2]], f[corner_offset[3]],
                                           f[corner_offset[4]], f[corner_offset[5]],
                                           f[corner_offset[6]], f[corner_offset[7]]};
          field_out[m][node] = trilinear(v, st.f[0], st.f[1], st.f[2]);
        }
      }
    }
}

}  // namespace shellflow::grid_fluid
