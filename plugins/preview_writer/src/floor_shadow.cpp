#include "shellflow/preview_writer/floor_shadow.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

namespace shellflow::preview_writer {

FloorShadow::FloorShadow(int floor_side) : m_axis(floor_side / 2) {}

double FloorShadow::Map::at(double u, double v) const {
  if (u < lower_u || u > upper_u || v < lower_v || v > upper_v) return 0.0;
  const double gu = std::clamp((u - u0) / dx, 0.0, static_cast<double>(nu - 1));
  const double gv = std::clamp((v - v0) / dx, 0.0, static_cast<double>(nv - 1));
  const int i = std::min(static_cast<int>(gu), std::max(nu - 2, 0));
  const int j = std::min(static_cast<int>(gv), std::max(nv - 2, 0));
  const double wu = nu > 1 ? gu - i : 0.0;
  const double wv = nv > 1 ? gv - j : 0.0;
  const int i1 = std::min(i + 1, nu - 1);
  const int j1 = std::min(j + 1, nv - 1);
  auto value = [&](int a, int b) { return values[static_cast<size_t>(a) + nu * b]; };
  return (1.0 - wv) * ((1.0 - wu) * value(i, j) + wu * value(i1, j)) +
         wv * ((1.0 - wu) * value(i, j1) + wu * value(i1, j1));
}

template <class Column>
void FloorShadow::add(const sdk::FieldView& field, Column&& column) {
  const int a = m_axis, u = (a + 1) % 3, v = (a + 2) % 3;
  // Sample (i, j, k) at i + n0 (j + n1 k) (sdk::FieldView).
  const std::ptrdiff_t stride[3] = {1, field.dims[0],
                                    static_cast<std::ptrdiff_t>(field.dims[0]) * field.dims[1]};
  const double pad = field.location == sdk::FieldView::Location::Cell ? 0.5 * field.dx : 0.0;
  Map m;
  m.u0 = field.origin[u];
  m.v0 = field.origin[v];
  m.dx = field.dx;
  m.nu = field.dims[u];
  m.nv = field.dims[v];
  m.lower_u = m.u0 - pad;
  m.upper_u = m.u0 + (m.nu - 1) * m.dx + pad;
  m.lower_v = m.v0 - pad;
  m.upper_v = m.v0 + (m.nv - 1) * m.dx + pad;
  m.values.resize(static_cast<size_t>(m.nu) * m.nv);
  for (int j = 0; j < m.nv; ++j)
    for (int i = 0; i < m.nu; ++i)
      m.values[static_cast<size_t>(i) + static_cast<size_t>(m.nu) * j] =
          column(field.data[0] + i * stride[u] + j * stride[v], field.dims[a], stride[a]);
  m_maps.push_back(std::move(m));
}

void FloorShadow::add_water(const sdk::FieldView& phi) {
  add(phi, [&](const double* column, int n, std::ptrdiff_t stride) {
    double lowest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < n; ++k) lowest = std::min(lowest, column[k * stride]);
    return std::clamp(0.5 - lowest / phi.dx, 0.0, 1.0);
  });
}

void FloorShadow::add_smoke(const sdk::FieldView& density, double sigma) {
  add(density, [&](const double* column, int n, std::ptrdiff_t stride) {
    double sum = 0.0;
    for (int k = 0; k < n; ++k) sum += column[k * stride];
    return 1.0 - std::exp(-sigma * sum * density.dx);
  });
}

double FloorShadow::at(const Eigen::Vector3d& p) const {
  double lit = 1.0;
  for (const Map& m : m_maps) lit *= 1.0 - m.at(p[(m_axis + 1) % 3], p[(m_axis + 2) % 3]);
  return 1.0 - lit;
}

}  // namespace shellflow::preview_writer
