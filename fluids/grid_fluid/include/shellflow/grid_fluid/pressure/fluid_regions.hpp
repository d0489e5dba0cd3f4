#pragma once
// FluidRegions: the connected fluid regions of the MAC cells (§4.3, Guendelman et al.
// 2005): a flood fill through every face that is not closed (Neumann). A region that
// reaches no open (Dirichlet, p = 0) domain face is enclosed — a pocket, a sealed side —
// and its pressure system is singular: it needs a compatible right-hand side, and CG
// needs its constant projected out (linear::ConstantNullSpace). Used by both pressure
// solves: the §4.3 projection and the §5.1 coupling pressure. With water (§4.4) only the
// liquid cells are filled: air cells are Dirichlet (p = 0), get region -1, and a region
// with an open face to an air cell is open.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/linear/constant_null_space.hpp"

namespace shellflow::grid_fluid {

struct FluidRegions {
  std::vector<int> region;             ///< region id of each cell (-1: air, not fluid)
  std::vector<std::uint8_t> enclosed;  ///< per region: 1 when it has no open domain face
  /// Per region: 1 for a single cell with every face closed (inside a source): it has no
  /// pressure unknown, its face velocities are all prescribed, its divergence is the
  /// source's to set (an emitter adds volume) and no solve can or should correct it.
  std::vector<std::uint8_t> sealed;
  std::vector<std::int64_t> start;  ///< CSR over the regions: cells of r are
  /// cells[start[r] .. start[r+1]), in cell order (4 bytes a cell: the pressure solves
  /// index cells with int, as linear::GridLaplacian does).
  std::vector<std::int32_t> cells;
  /// Set by update_fluid_regions: the labelling's inputs when they allow keeping it.
  bool keyed = false;
  std::uint64_t key = 0;

  int count() const { return static_cast<int>(enclosed.size()); }
  std::int64_t size(int r) const { return start[r + 1] - start[r]; }
  int enclosed_count() const;
  /// The constants of the enclosed regions that are not sealed (numbered in region
  /// order): the null space of the pressure operator. A sealed cell's row is zero, so its
  /// right-hand side must be zero: the caller sets it so. Empty when every such region is
  /// open. Unknown u is cell `unknowns[u]` (empty: unknown u is cell u).
  linear::ConstantNullSpace null_space(std::span<const std::int64_t> unknowns = {}) const;
};

/// Labels the regions of the cells of `grid` connected through faces whose flag in
/// `closed[axis]` (one byte per face of family axis, UniformGrid::index order) is 0.
/// A region is open when one of its cells has a non-closed domain face of type Open, or
/// a non-closed face to an air cell. `liquid` (one byte per cell; empty: every cell is
/// fluid) marks the liquid cells of a water scene. `interior_closed` false promises that
/// no interior face is closed (no shell) and there is no air: then the grid is one region
/// and the fill is skipped.
void label_fluid_regions(const grid::UniformGrid& grid,
                         const std::array<std::vector<std::uint8_t>, 3>& closed,
                         const DomainBoundary& boundary, FluidRegions& out,
                         bool interior_closed = true, std::span<const std::uint8_t> liquid = {});

/// label_fluid_regions, unless `out` was labelled by this function from the same inputs:
/// no water, and the same closed faces (grid::fingerprint), open sides and
/// interior_closed — a smoke scene whose shells stand still, or whose only moving shells
/// leave their faces open (a two-way cloth in the §5.1 solve). Returns true when it
/// labelled.
bool update_fluid_regions(const grid::UniformGrid& grid,
                          const std::array<std::vector<std::uint8_t>, 3>& closed,
                          const DomainBoundary& boundary, FluidRegions& out,
                          bool interior_closed = true, std::span<const std::uint8_t> liquid = {});

}  // namespace shellflow::grid_fluid
