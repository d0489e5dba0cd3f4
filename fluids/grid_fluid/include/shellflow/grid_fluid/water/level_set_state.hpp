#pragma once
// The water's level set in a saved state (GridFluid::save/restore, checkpoints): its layout
// (/fluid/water/level_set, "nodes" or "cells"), then φ. A state holds φ on one layout and
// restores only into a level set of the same one: the two have other sample counts, and
// where the counts could agree the samples would still mean other points.
//
// The layout is written as a negative 64-bit tag (−1 nodes, −2 cells) in the place where
// states saved before the layout was recorded hold φ's column length (never negative).
// Those older states are all on the nodes, and still restore into a node level set.

#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::grid_fluid {

/// The layout's name as a scene writes it in /fluid/water/level_set.
const char* layout_name(LevelSet::Layout layout);

/// Writes the layout tag and φ.
void save_level_set(sdk::StateWriter& out, const LevelSet& level_set);

/// Reads what save_level_set() wrote (or an untagged node φ) into `level_set`'s φ.
/// @throw Error naming both layouts and what to do when the state's layout is not
/// level_set's; @throw Error when φ has another size (another grid).
void restore_level_set(sdk::StateReader& in, LevelSet& level_set);

}  // namespace shellflow::grid_fluid
