#pragma once
// FloorShadow: the shadow that a light straight above (against gravity) casts on the floor
// from the water and the smoke. Water in mid-air throws its shadow on the floor below it,
// apart from itself in the image; a pool throws it underneath, where it touches the
// floor. With the walls (DomainWalls) this is what tells the two apart.
//
// One value per column of a field's samples along the floor's axis (a 2-D map over the
// floor, recomputed per frame: one pass over the field):
//   water (level set φ, signed distance near the surface):
//     s = clamp(1/2 − min φ / dx, 0, 1) over the column: 1 where the column holds water,
//     0 half a cell clear of it, a cell-wide penumbra between;
//   smoke (density ρ): s = 1 − exp(−σ Σ ρ dx) over the column (Beer–Lambert straight down,
//     the renderer's σ; node and cell samples alike stand for dx of the column each).
// Between columns s is bilinear (the nearest outer column's value beyond the outer ones,
// 0 outside the field's box); water and smoke combine as 1 − (1 − s_water)(1 − s_smoke).
// The floor's colour is multiplied by 1 − strength · s.
//
// Defined in this header for the reason given in domain_walls.hpp.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

class FloorShadow {
 public:
  /// For the floor on side `floor_side` (2 axis + max_side, DomainWalls::floor()).
  explicit FloorShadow(int floor_side) : m_axis(floor_side / 2) {}

  /// Adds the water's shadow from its level set (a non-empty scalar field).
  void add_water(const sdk::FieldView& phi) {
    add(phi, [&](const double* column, int n, std::ptrdiff_t stride) {
      double lowest = std::numeric_limits<double>::infinity();
      for (int k = 0; k < n; ++k) lowest = std::min(lowest, column[k * stride]);
      return std::clamp(0.5 - lowest / phi.dx, 0.0, 1.0);
    });
  }

  /// Adds the smoke's shadow from its density (a non-empty scalar field), absorption σ.
  void add_smoke(const sdk::FieldView& density, double sigma) {
    add(density, [&](const double* column, int n, std::ptrdiff_t stride) {
      double sum = 0.0;
      for (int k = 0; k < n; ++k) sum += column[k * stride];
      return 1.0 - std::exp(-sigma * sum * density.dx);
    });
  }

  /// The shadow in [0, 1] at world point p (on the floor).
  double at(const Eigen::Vector3d& p) const {
    double lit = 1.0;
    for (const Map& m : m_maps) lit *= 1.0 - m.at(p[(m_axis + 1) % 3], p[(m_axis + 2) % 3]);
    return 1.0 - lit;
  }

  bool empty() const { return m_maps.empty(); }

 private:
  /// One field's shadow over the floor: values at the columns (u, v), u fastest.
  struct Map {
    double u0 = 0.0, v0 = 0.0;  ///< position of column (0, 0)
    double dx = 1.0;
    int nu = 0, nv = 0;
    double lower_u = 0.0, upper_u = 0.0, lower_v = 0.0, upper_v = 0.0;  ///< the box
    std::vector<double> values;

    double at(double u, double v) const {
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
  };

  /// `column(first sample, count, stride)` → the column's shadow, for every column.
  template <class Column>
  void add(const sdk::FieldView& field, Column&& column) {
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

  int m_axis = 1;
  std::vector<Map> m_maps;
};

}  // namespace shellflow::preview_writer
