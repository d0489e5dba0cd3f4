#pragma once
// Where the water of cut cells' parts goes when the shells move (issue #52, docs/cut-cells.md
// §2.7). A part whose cell keeps the same parts (the same groups of corners: no shell crossed
// a node) keeps its water: the projection balanced its fragments against the shell's sweep,
// so its water already grew or shrank with it. A part whose cell's parts changed (a node
// swept: a part vanished, appeared or changed its corners) hands its water to the parts its
// samples reach when each rides its nearest shell point, those that still see that point's
// side after the move (never across a shell: a sample by a cup's bottom, which does not move
// across it, may be crossed by the wall): into the next cell where the shell left the part
// behind. Within what the samples reach the water goes where the level set after the move
// shows water, or, a film it does not show, next to the shell.

#include <span>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/volume_fraction.hpp"

namespace shellflow::grid_fluid {

/// Adds the water `water_before` of each part of `before` (cut by `shells_before`) to
/// `fraction`, whose cut cells must already be `after`'s (cut by `shells_after`): a whole
/// cell's or a slot's in values(), an extra part's in part_values(). A part none of whose
/// samples lands keeps its water in its cell, in the part holding most of its corners (the
/// slot among equals).
void carry_part_water(const grid::UniformGrid& grid, const CellParts& before,
                      std::span<const double> water_before, const ShellGeometry& shells_before,
                      const CellParts& after, const ShellGeometry& shells_after,
                      const LevelSet& level_set, VolumeFraction& fraction);

}  // namespace shellflow::grid_fluid
