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

#include <Eigen/Core>
#include <vector>

#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

class FloorShadow {
 public:
  /// For the floor on side `floor_side` (2 axis + max_side, DomainWalls::floor()).
  explicit FloorShadow(int floor_side);

  /// Adds the water's shadow from its level set (a non-empty scalar field).
  void add_water(const sdk::FieldView& phi);

  /// Adds the smoke's shadow from its density (a non-empty scalar field), absorption σ.
  void add_smoke(const sdk::FieldView& density, double sigma);

  /// The shadow in [0, 1] at world point p (on the floor).
  double at(const Eigen::Vector3d& p) const;

  bool empty() const { return m_maps.empty(); }

 private:
  /// One field's shadow over the floor: values at the columns (u, v), u fastest.
  struct Map {
    double u0 = 0.0, v0 = 0.0;  ///< position of column (0, 0)
    double dx = 1.0;
    int nu = 0, nv = 0;
    double lower_u = 0.0, upper_u = 0.0, lower_v = 0.0, upper_v = 0.0;  ///< the box
    std::vector<double> values;

    /// The bilinear value at (u, v); 0 outside the box.
    double at(double u, double v) const;
  };

  /// `column(first sample, count, stride)` → the column's shadow, for every column.
  /// Defined in floor_shadow.cpp, the only place it is used.
  template <class Column>
  void add(const sdk::FieldView& field, Column&& column);

  int m_axis = 1;
  std::vector<Map> m_maps;
};

}  // namespace shellflow::preview_writer
