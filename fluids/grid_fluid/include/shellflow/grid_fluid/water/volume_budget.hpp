#pragma once
// VolumeBudget: the water a scene gains and loses by design, so that its volume can be
// checked against what it should hold: V(t) = V(0) + added − outflow, up to the solver's
// own error (water_volume_drift in metrics.csv).
//  - added: what the emitters give, counted over a control volume about each (the box of
//    cells its water may lie in): what the box gains plus what the velocity carries out
//    of it. Held faces keep an emitter full, so the level set's advection refills it from
//    upstream as often as apply() does; the flow out of it is the emission either way.
//  - outflow: what the velocity carries out through the domain's open sides (in through
//    them, negative).
// Flows are the node velocities' (those φ moves with) over each step, swept: across a
// face, what lies upstream within u_n dt of it (u_n the mean normal velocity of its four
// nodes), the face's wet area (φ's linear interpolant below zero on its two triangles, the
// triangles LevelSet::volume's tetrahedra cut it into) integrated over that depth.

#include <array>

#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/water_source.hpp"

namespace shellflow::grid_fluid {

struct VolumeBudget {
  double added = 0.0;    ///< [m^3] by the emitters since the start
  double outflow = 0.0;  ///< [m^3] through the open sides since the start
};

/// The fraction of a square face where φ's linear interpolant on its two triangles (about
/// the diagonal from corner 0 to corner 3) is below zero; corners c = i + 2j over the
/// face's two axes.
double face_water_fraction(const std::array<double, 4>& corner);

/// The cells an emitter's water may lie in: those about its nodes (apply() sets φ <= 0
/// only inside it), clamped to the grid. The budget's control volume for it: what it adds
/// is what these cells gain plus what flows out of them.
grid::IndexBox emitter_cells(const grid::UniformGrid& grid, const WaterSource& source);

/// The net water [m^3] that `velocity` carries out of the box of `cells` in a step of dt,
/// from φ at its start (inflow counts negative); across the domain's sides only where
/// they are open (`open[2 * axis + max_side]`). The whole grid's box: the open sides'
/// outflow.
double box_outflow(const LevelSet& level_set, const NodeFields& velocity,
                   const grid::IndexBox& cells, const std::array<bool, 6>& open, double dt);

}  // namespace shellflow::grid_fluid
