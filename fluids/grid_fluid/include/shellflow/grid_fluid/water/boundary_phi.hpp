#pragma once
// BoundaryPhi: φ beyond the outermost cell centres while the cell-centred φ is advected
// (docs/water-cell-centres.md §2.2; PhysBAM's BOUNDARY_PHI_WATER, Fill_Single_Ghost_Region).
// A departure point beyond a side reads, in each row of cells square to that side, a ghost
// continued from the row's first cell b: φ_b (constant continuation, what every other phase
// reads) unless the side is open or an inflow and the normal velocity on the row's boundary
// face points into the domain. There the face is the water's surface and nothing enters
// from outside (issue #51; PhysBAM lets water in below a tolerance, here there is none):
// φ at a distance e beyond b is max(−Δx/2, φ_b) + e, PhysBAM's ghost cells (e = Δx, 2Δx,
// 3Δx) and the line through them continued to b, so that deep water pulls away from the side
// as fast as its face moves (PhysBAM's interpolation from φ_b to its first ghost does not:
// docs/water-cell-centres.md, C3). Across rows φ is trilinear as inside. Walls are never
// ruled: their faces hold no normal velocity, so constant continuation.
// Fast marching reads the same ghost (FastMarching::set_ghost): it sets every cell it does
// not reach from a surface to ±band, which would make such water deep again each step.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::grid_fluid {

class MacGrid;

class BoundaryPhi {
 public:
  /// The rows whose boundary face's normal velocity in `mac` points into the domain, on the
  /// sides flagged in `ruled` (2 * axis + max_side: the open and inflow sides). `lattice`:
  /// φ's, the nodes at the centres of mac's cells (LevelSet::cell_centre_lattice).
  void update(const grid::UniformGrid& lattice, const MacGrid& mac,
              const std::array<bool, 6>& ruled);
  /// Does some row of some side pull away (else φ beyond every side is constant)?
  bool any() const { return m_any[0] || m_any[1] || m_any[2] || m_any[3] || m_any[4] || m_any[5]; }
  /// φ at any point p: trilinear on the lattice where p lies within its box, the rule
  /// above across the sides it lies beyond (each side's rule in turn at an edge or corner).
  /// `lo`, `hi`: the least and greatest of the eight values interpolated.
  double sample(std::span<const double> phi, const Eigen::Vector3d& p, double& lo,
                double& hi) const;
  /// Does the row of lattice node `node` (on side `side`'s outer plane) pull away there?
  bool pulls(int side, const Eigen::Vector3i& node) const {
    if (!m_any[side]) return false;
    const int a = side / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    return m_inward[side][node[b] +
                          std::size_t(m_lattice.counts(grid::Location::Node)[b]) * node[c]] != 0;
  }
  /// φ at `distance` [m] > 0 beyond a first cell holding φ_b whose face lets nothing in.
  static double pulled_away(double phi_b, double distance, double dx);

 private:
  grid::UniformGrid m_lattice;
  /// Per side, per row (first tangential axis fastest): 1 where the face points inward.
  std::array<std::vector<std::uint8_t>, 6> m_inward;
  std::array<bool, 6> m_any{};
};

}  // namespace shellflow::grid_fluid
