#pragma once
// VolumeBudget: the water a scene gains and loses by design, so that its volume can be
// checked against what it should hold: V(t) = V(0) + added − outflow, up to the solver's
// own error (water_volume_drift in metrics.csv).
//  - added: what the emitters give as their scene asks it. One with a velocity: its fill
//    (what apply() sets the first step it has no water) and then the flow its held faces
//    impose on the divergence-free velocity (their area × the velocity), however the level
//    set carries it; what apply() sets later (topping its rim up where the stream pulls
//    away, or its cells as the advection empties them) is not counted again, so water the
//    level set makes or loses about and downstream of it shows as drift. One without a
//    velocity: whatever apply() sets (its water leaves by the fluid's own velocity and
//    apply() tops it up).
//  - outflow: what the velocity carries out through the domain's open sides: out only, as
//    nothing enters there (BoundaryPhi), so it never decreases.
// The open sides' flow over each step is swept: across a face, what lies upstream within
// u_n dt of it, the face's wet area (φ's linear interpolant below zero on its two
// triangles) integrated over that depth; u_n the MAC face's (what the centres' velocities
// average), the corners the mean of the four rows of centres about them, φ linear along
// the normal from the face through the first two centres.

#include <array>

#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/water_source.hpp"

namespace shellflow::grid_fluid {

class MacGrid;

struct VolumeBudget {
  double added = 0.0;    ///< [m^3] by the emitters since the start
  double outflow = 0.0;  ///< [m^3] through the open sides since the start
};

/// Where the drift arose, with "volume_by_phase" on: the water measured between the phases
/// of each step (five more measures a step), each phase's change summed since the start
/// [m^3]. Their sum is water_volume_drift, exactly without shells; with shells, up to the
/// measure's change at the last step's report (cells a shell cuts count two-sided only in
/// the band of cells of the step).
struct PhaseDrift {
  double advection = 0.0;         ///< φ's advection and the emitters, less the budget's flows
  double shells = 0.0;            ///< the shells' move n → n+1 and the refill of swept cells
  double reinitialization = 0.0;  ///< the particles' corrections and fast marching
  double between_steps = 0.0;     ///< the measure's own change from one step to the next
};

/// The fraction of a square face where φ's linear interpolant on its two triangles (about
/// the diagonal from corner 0 to corner 3) is below zero; corners c = i + 2j over the
/// face's two axes.
double face_water_fraction(const std::array<double, 4>& corner);

/// The MAC cells whose water, as LevelSet::volume measures it, an emitter's apply() may
/// change: those about the samples it sets (within the level set's band of it), clamped
/// to the grid.
grid::IndexBox emitter_reach(const LevelSet& level_set, const WaterSource& source);

/// Does any of the emitter's own cells (their centre inside it) hold water (φ below zero)?
bool emitter_has_water(const LevelSet& level_set, const WaterSource& source);

/// The flow [m^3/s] the emitter's held faces let out while it is on (t: a time it is on;
/// the same at any): over the faces between its cells and the rest of the domain, the held
/// velocity's outward part × Δx². What they impose on the divergence-free velocity,
/// exactly: the cells' staircase, not π r² for a cylinder. `grid`: the MAC grid.
double emitter_held_flow(const grid::UniformGrid& grid, const WaterSource& source, double t);

/// The water [m^3] that the faces of `mac` carry out through the open sides of the domain
/// (`open[2 * axis + max_side]`) in a step of dt, from φ at its start; faces whose velocity
/// points in count nothing.
double open_side_outflow(const LevelSet& level_set, const MacGrid& mac,
                         const std::array<bool, 6>& open, double dt);

}  // namespace shellflow::grid_fluid
