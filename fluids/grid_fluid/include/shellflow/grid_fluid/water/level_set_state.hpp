#pragma once
// The water's level set in a saved state (GridFluid::save/restore, checkpoints): a tag for
// where φ lives, then φ. States are written with the cell-centred tag (−2). The tag −1 and
// untagged states (a column length, never negative, in the tag's place) hold φ on the grid's
// nodes, from versions before the node level set was removed: they are refused, naming the
// change, since their samples mean other points.

#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::grid_fluid {

/// Writes the cell-centred tag and φ.
void save_level_set(sdk::StateWriter& out, const LevelSet& level_set);

/// Reads what save_level_set() wrote into `level_set`'s φ.
/// @throw Error naming the removed node level set for a state that holds φ on the nodes;
/// @throw Error when φ has another size (another grid).
void restore_level_set(sdk::StateReader& in, LevelSet& level_set);

}  // namespace shellflow::grid_fluid
