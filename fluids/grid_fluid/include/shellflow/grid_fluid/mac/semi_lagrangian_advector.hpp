#pragma once
// SemiLagrangianAdvector: §4.1 (Guendelman et al. 2005) on the nodes. From each node x a
// ray is traced to x − Δt u and clipped against wedges of doubled thickness ε' = 2ε, so
// the base interpolation point is visible from x; from that point 8 secondary rays (ε)
// go to the nodes of the trilinear stencil, and every stencil node that is not visible
// is replaced by the object value: the object velocity where the ray met the shell,
// zero density, the ambient temperature. Nodes outside the shell band take the plain
// fast path (the band is grown by Δt max|u| + 2Δx so that neither ray nor stencil of a
// node outside it can reach a shell).

#include <cstdint>
#include <span>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {

class SemiLagrangianAdvector {
 public:
  SemiLagrangianAdvector(const grid::UniformGrid& grid, double ambient_temperature)
      : m_grid(grid), m_ambient(ambient_temperature) {}

  /// out = in advected by in's own velocity over dt. `band` may be null (no shells).
  /// `out` must be sized like `in` (NodeFields of the same grid). `active` (one byte per
  /// node; empty: every node) limits the work to the flagged nodes; the others keep `in`.
  void advect(const NodeFields& in, NodeFields& out, double dt, const ShellGeometry& shells,
              const geometry::ShellBand* band, std::span<const std::uint8_t> active = {}) const;

  /// The band margin that makes the fast path safe for a step dt at speed max_speed.
  double band_margin(double dt, double max_speed) const {
    return dt * max_speed + 2.0 * m_grid.dx();
  }

 private:
  grid::UniformGrid m_grid;
  double m_ambient;
};

}  // namespace shellflow::grid_fluid
