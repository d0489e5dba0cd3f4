#pragma once
// PressureProjection: §4.3 (Guendelman et al. 2005). Makes the MAC face velocities
// divergence free, u = u* − Δt ∇p with ∇²p = ∇·u*/Δt (eq. (3)–(4)), where
//  - a face is Neumann when the segment between its two cell centres meets a shell
//    (Fig. 5; rays only in the shell band) or it is a wall/inflow face of the domain; a
//    Neumann face keeps the velocity of the object there (the effective velocity of §4.3,
//    set on the ShellGeometry by the caller) and is left out of the Laplacian;
//  - open domain faces are Dirichlet (p = 0 outside);
//  - a flood fill over the cells through the non-Neumann faces finds the fluid regions;
//    a region with no Dirichlet face (enclosed: a pocket, a sealed side) gets the
//    compatibility correction of §4.3 [Peyret and Taylor 1983]: its net boundary flux is
//    spread uniformly over its boundary faces; regions are corrected smallest first, and
//    faces shared with an already corrected region are left alone so that it stays
//    compatible (a pocket corrects the faces it shares with its surroundings, the
//    surroundings then correct their walls);
//  - each region is solved on its own: PCG with MIC(0) in double precision
//    (linear::PcgMic0Solver; enclosed regions as consistent semidefinite systems) or a
//    CHOLMOD factorisation (linear::CholmodSolver; enclosed regions with one diagonal
//    entry raised by 1, exact for a consistent right-hand side).
// Unknowns are the scaled pressures p' = p Δt / Δx, so the system is the graph Laplacian
// of the fluid cells, A p' = −Σ_faces u*·n (per cell), and u_f = u*_f − (p'_+ − p'_−).

#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac_grid.hpp"
#include "shellflow/grid_fluid/shell_geometry.hpp"

namespace shellflow::grid_fluid {

enum class PressureSolver { Pcg, Cholmod };

struct ProjectionSettings {
  PressureSolver solver = PressureSolver::Pcg;
  /// Relative residual |b − A p| / |b| of each region's solve; tightened so that the
  /// largest cell divergence after projection is also <= tolerance × max|u*|.
  double tolerance = 1e-6;
  int max_iterations = 2000;
};

struct ProjectionStats {
  int regions = 0;            ///< connected fluid regions
  int enclosed_regions = 0;   ///< regions without a Dirichlet face (compatibility corrected)
  int iterations = 0;         ///< PCG iterations, summed over the regions
  int max_region_iterations = 0;
  double relative_residual = 0.0;  ///< largest over the regions
  bool converged = true;
  std::int64_t shell_neumann_faces = 0;  ///< faces closed by a shell (Fig. 5)
  double max_compatibility_flux = 0.0;   ///< largest |net boundary flux| corrected [m^3/s / dx^2]
  /// max over cells |Σ u·n| / max|u| after projection (= |∇·u| Δx / max|u|).
  double max_relative_divergence = 0.0;
};

class PressureProjection {
 public:
  PressureProjection(const grid::UniformGrid& grid, ProjectionSettings settings);

  const ProjectionSettings& settings() const { return m_settings; }

  /// Projects `mac` in place. `band` (may be null without shells) lists the faces where
  /// rays are cast. `mac.pressure()` receives p [Pa/(kg/m^3)].
  ProjectionStats project(MacGrid& mac, double dt, const DomainBoundary& boundary,
                          const ShellGeometry& shells, const geometry::ShellBand* band);

  /// Neumann flags of the last projection for face family `axis`.
  const std::vector<std::uint8_t>& neumann(int axis) const { return m_neumann[axis]; }
  /// Region id of each cell in the last projection.
  const std::vector<int>& region() const { return m_region; }
  /// Scaled pressures p' = p Δt / Δx of the last projection (the next initial guess; part
  /// of the solver state for save/restore).
  std::vector<double>& scaled_pressure() { return m_scaled; }
  /// Whether region r has no Dirichlet face.
  bool enclosed(int r) const { return m_enclosed[r] != 0; }

 private:
  void mark_neumann(MacGrid& mac, const DomainBoundary& boundary, const ShellGeometry& shells,
                    const geometry::ShellBand* band, ProjectionStats& stats);
  void flood_fill(const DomainBoundary& boundary);
  void correct_compatibility(MacGrid& mac, ProjectionStats& stats);
  void solve_region(int r, const MacGrid& mac, const DomainBoundary& boundary, double scale,
                    ProjectionStats& stats);

  void apply_pressure(MacGrid& mac) const;
  /// max over cells |Σ u·n|.
  double max_cell_divergence(const MacGrid& mac) const;
  /// Neighbour of cell `c` across its face (axis, side): the cell, or -1 outside.
  std::int64_t neighbour(const Eigen::Vector3i& c, int axis, int side) const;
  /// Face flat index of cell `c`'s face (axis, side).
  std::int64_t face_of(const Eigen::Vector3i& c, int axis, int side) const {
    Eigen::Vector3i f = c;
    f[axis] += side;
    return m_grid.index(face_location(axis), f);
  }

  grid::UniformGrid m_grid;
  ProjectionSettings m_settings;
  std::array<std::vector<std::uint8_t>, 3> m_neumann;
  std::vector<int> m_region;
  std::vector<std::uint8_t> m_enclosed;
  std::vector<std::int64_t> m_region_start;  ///< CSR of the cells of each region
  std::vector<std::int64_t> m_region_cells;
  std::vector<int> m_row;       ///< cell -> row in its region's system
  std::vector<double> m_scaled; ///< p' = p Δt / Δx, kept as the next initial guess
};

}  // namespace shellflow::grid_fluid
