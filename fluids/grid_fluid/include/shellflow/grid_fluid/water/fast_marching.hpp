#pragma once
// FastMarching: reinitialises the water's level set to a signed distance within a band
// (§4.4.1, Guendelman et al. 2005; first-order fast marching, Sethian 1996, as in Osher
// and Fedkiw 2002 ch. 7), never across a thin shell:
//  - the interface nodes are those with a sign change to a *visible* axis neighbour,
//    plus every node with φ <= 0 whose neighbour across a shell (not visible) is air; a
//    node with φ > 0 and no visible neighbour with φ <= 0 is not one (water has no
//    influence across the shell);
//  - each interface node's distance combines, over the axes, the distance to the
//    crossing along that axis (linear interpolation, φ_i / (φ_i − φ_j) Δx) — for φ > 0
//    only towards visible neighbours; for φ <= 0 towards air hidden by a shell,
//    min(distance to the shell along that edge, |φ|) (an interface against the solid, so
//    that water does not stick to it): |φ| = 1 / sqrt(Σ_axes 1/d_a^2).
//    §4.4.1 adds *every* water node with a hidden neighbour; we add only those with air
//    behind the shell: a shell under water (water on both sides) is no surface, and
//    shrinking |φ| along it turned the cells where it pierces the surface into air (a
//    still pool about a tilted plate lost 1% of its volume per step and began to flow);
//  - the march accepts nodes in increasing |φ|, each from its accepted visible neighbours
//    of the same sign (the upwind quadratic of the eikonal equation |∇φ| = 1), and stops
//    at the band; nodes beyond it are set to ±band.
// Visibility is decided by rays only for nodes in the shell band.

#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {

struct FastMarchingStats {
  std::int64_t interface_nodes = 0;  ///< nodes initialised from the surface
  std::int64_t marched_nodes = 0;    ///< nodes accepted by the march (the band's work)
};

class FastMarching {
 public:
  explicit FastMarching(const grid::UniformGrid& grid);

  /// Reinitialises `phi` (node values) to a signed distance within `band` [m].
  FastMarchingStats reinitialize(std::span<double> phi, double band, const ShellGeometry& shells,
                                 const geometry::ShellBand* shell_band);

 private:
  grid::UniformGrid m_grid;
  /// Per node, bit 2a + side: the neighbour along axis a (side 0: −, 1: +) is not visible.
  std::vector<std::uint8_t> m_hidden;
  std::vector<std::int64_t> m_hidden_list;  ///< nodes with a bit set (cleared next time)
  std::vector<double> m_distance;           ///< |φ| being built; +inf: not reached
  std::vector<std::uint8_t> m_accepted;
};

}  // namespace shellflow::grid_fluid
