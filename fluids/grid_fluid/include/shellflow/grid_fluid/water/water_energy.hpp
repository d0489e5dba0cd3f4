#pragma once
// water_energy: the kinetic and potential energy of the water of a MAC grid, read through
// the projection's view of the liquid (FreeSurface: φ at the cell centres), and its
// largest speeds on liquid faces and on thin surface faces (issue #51, "no energy from
// nowhere"; docs/water-cell-centres.md §3 C0 and §4).
//
// Kinetic energy is the norm the ghost-fluid projection minimises (Batty et al. 2007;
// Ng et al. 2009): K = ½ρ Σ_f w_f u_f² Δx³ with w_f
//   1  between two liquid cells (φ <= 0, the projection's liquid test),
//   θ  between a liquid and an air cell, θ = φ_l / (φ_l − φ_a) clamped as the projection
//      clamps it (free_surface_inverse_theta; 1 with first-order surface pressure),
//   ½  on a domain side next to a liquid cell: half its staggered control volume lies in
//      the domain, so in a full tank each axis's weights sum to the water's volume
//      (a closed side's face holds the wall's velocity, normally 0: no energy there),
//   0  between two air cells (extrapolated velocities, no water).
// Faces closed by a shell are weighted as any other face (they hold the shell's velocity).
// Potential energy P = −ρ Σ_c V_c g·x_c, V_c = clamp(½ − φ_c/Δx, 0, 1) Δx³: the first-order
// water fraction of cell c, exact for a plane parallel to a cell face, and the mass at
// the cell centre, so P errs by at most ρ|g| Δx²/8 per unit area of surface (a cell a
// fraction f full holds its water f(1 − f)Δx/2 off its centre).

#include <Eigen/Core>
#include <span>

#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/pressure/pressure_projection.hpp"

namespace shellflow::grid_fluid {

struct WaterEnergy {
  double kinetic = 0.0;    ///< ½ρ Σ_f w_f u_f² Δx³ [J]
  double potential = 0.0;  ///< −ρ Σ_c V_c g·x_c [J] (zero at the grid's origin)
  double mass = 0.0;       ///< ρ Σ_c V_c [kg]
  /// Largest |u_f| over the faces whose φ_face = ½(φ_i + φ_j) <= 0 (a domain side's face:
  /// its one cell's φ), the faces PhysBAM keeps through its extrapolation [m/s].
  double max_liquid_speed = 0.0;
  /// Largest |u_f| over the faces between a liquid and an air cell whose geometric θ is
  /// below ½ (φ_face > 0, whatever the projection's θ): the faces w hides from K [m/s].
  double max_surface_face_speed = 0.0;
};

/// The first-order water fraction of a cell whose centre has level set value `phi`.
double water_cell_fraction(double phi, double dx);

/// The energy of the water in `mac` (its face velocities as they stand) whose cells
/// `surface` gives (cell_phi: one value per cell of mac.grid()); `density` ρ [kg/m^3],
/// `gravity` g [m/s^2]. `fraction`, when given (the water fraction per cell, "volume_fraction"),
/// is each cell's water for the potential energy and the mass instead of the first-order
/// fraction of its φ. Sums are ordered_sum's: the same bits on any number of threads.
WaterEnergy water_energy(const MacGrid& mac, const FreeSurface& surface, double density,
                         const Eigen::Vector3d& gravity,
                         std::span<const double> fraction = {});

}  // namespace shellflow::grid_fluid
