#pragma once
// FluidRegions: the connected fluid regions of the MAC cells (§4.3, Guendelman et al.
// 2005): a flood fill through every face that is not closed (Neumann). A region that
// reaches no open (Dirichlet, p = 0) domain face is enclosed — a pocket, a sealed side —
// and its pressure system is singular: it needs a compatible right-hand side.

#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/domain_boundary.hpp"

namespace shellflow::grid_fluid {

struct FluidRegions {
  std::vector<int> region;               ///< region id of each cell
  std::vector<std::uint8_t> enclosed;    ///< per region: 1 when it has no open domain face
  std::vector<std::int64_t> start;       ///< CSR over the regions: cells of r are
  std::vector<std::int64_t> cells;       ///< cells[start[r] .. start[r+1]), in cell order

  int count() const { return static_cast<int>(enclosed.size()); }
  std::int64_t size(int r) const { return start[r + 1] - start[r]; }
};

/// Labels the regions of the cells of `grid` connected through faces whose flag in
/// `closed[axis]` (one byte per face of family axis, UniformGrid::index order) is 0.
/// A region is open when one of its cells has a non-closed domain face of type Open.
void label_fluid_regions(const grid::UniformGrid& grid,
                         const std::array<std::vector<std::uint8_t>, 3>& closed,
                         const DomainBoundary& boundary, FluidRegions& out);

}  // namespace shellflow::grid_fluid
