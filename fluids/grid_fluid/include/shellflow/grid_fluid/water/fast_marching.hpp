#pragma once
// FastMarching: reinitialises the water's level set to a signed distance within a band
// (§4.4.1, Guendelman et al. 2005; fast marching, Sethian 1996, as in Osher and Fedkiw
// 2002 ch. 7, with second-order upwind differences where two accepted nodes allow),
// never across a thin shell:
//  - the interface nodes are those with a sign change to a *visible* axis neighbour; a
//    node with φ > 0 and no visible neighbour with φ <= 0 is not one (water has no
//    influence across the shell). Each one's distance is |φ|/|∇φ| (central differences
//    over its visible neighbours, one-sided where only one is visible or the other lies
//    across the surface and is held, below: a held node's |φ| may be its distance to the
//    shell, not a slope of the surface), no more than the nearest crossing along an axis
//    (linear interpolation, φ_i / (φ_i − φ_j) Δx, towards visible neighbours only). The
//    paper's 1 / sqrt(Σ_axes 1/d_a^2), the plane through the axis crossings, understates
//    |φ| inside a convex surface and overstates it outside: reinitialised every step, water
//    shrank. A |∇φ| within 5% of 1 counts as 1: that much is the central differences' own
//    error on a surface curving with radius 2.5Δx, and dividing by it every step grew water;
//  - a node with a neighbour it cannot see is *held*: its distance is at most its own |φ|
//    (as an interface node, the smaller of the two; otherwise a tentative value the march
//    may still lower). The surface it is near may lie behind the shell's edge, where the
//    visible neighbours cannot tell; the advection that gave φ saw around it.
//    §4.4.1 instead puts every φ <= 0 node with a hidden neighbour on the interface at
//    min(distance to the shell, |φ|) in the hidden directions ("so that water does not
//    stick to objects"). That is not a fixed point of still water: where a shell meets
//    the surface it shrinks |φ| by up to a cell every step. Water cannot stick when held
//    either: a held node's |φ| never grows, and advection empties it;
//  - the march accepts nodes in increasing |φ|, each from its accepted visible neighbours
//    of the same sign (the upwind quadratic of the eikonal equation |∇φ| = 1; second order
//    along an axis where the next node upwind is accepted too and not held, an interface
//    node across the surface counting with its signed distance), and stops at the band;
//    nodes beyond it are set to ±band. First-order marched values a cell out overstate |φ|
//    and made the next pass's central differences move the surface.
// Visibility is decided by rays only for nodes in the shell band.

#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/water/boundary_phi.hpp"

namespace shellflow::grid_fluid {

struct FastMarchingStats {
  std::int64_t interface_nodes = 0;  ///< nodes initialised from the surface
  std::int64_t marched_nodes = 0;    ///< nodes accepted by the march (the band's work)
};

class FastMarching {
 public:
  explicit FastMarching(const grid::UniformGrid& grid);

  /// Reinitialises `phi` (node values) to a signed distance within `band` [m]. `scratch`,
  /// when given, holds the distances being built (any contents; the caller's spare buffer of
  /// φ's size), else the marcher's own.
  FastMarchingStats reinitialize(std::span<double> phi, double band, const ShellGeometry& shells,
                                 const geometry::ShellBand* shell_band,
                                 std::vector<double>* scratch = nullptr);
  /// φ beyond the lattice's sides for the marches that follow: a water node on a side whose
  /// row pulls away has the ghost beyond it as an air neighbour (BoundaryPhi); null (the
  /// default): no neighbour there, φ continued constant. Kept, not copied.
  void set_ghost(const BoundaryPhi* ghost) { m_ghost = ghost; }

 private:
  grid::UniformGrid m_grid;
  /// Per node, bit 2a + side: the neighbour along axis a (side 0: −, 1: +) is not visible.
  std::vector<std::uint8_t> m_hidden;
  std::vector<std::int64_t> m_hidden_list;  ///< nodes with a bit set (cleared next time)
  std::vector<double> m_distance;           ///< |φ| being built; +inf: not reached
  std::vector<std::uint8_t> m_accepted;
  std::vector<std::uint8_t> m_held;  ///< held next to a shell, not an interface node
  const BoundaryPhi* m_ghost = nullptr;
};

}  // namespace shellflow::grid_fluid
