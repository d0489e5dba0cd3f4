#pragma once
// PressureProjection: §4.3 (Guendelman et al. 2005). Makes the MAC face velocities
// divergence free, u = u* − Δt ∇p with ∇²p = ∇·u*/Δt (eq. (3)–(4)), where
//  - a face is Neumann when the segment between its two cell centres meets a shell
//    (Fig. 5; rays only in the shell band) or it is a wall/inflow face of the domain; a
//    Neumann face keeps the velocity of the object there (the effective velocity of §4.3,
//    set on the ShellGeometry by the caller) and is left out of the Laplacian;
//  - open domain faces are Dirichlet (p = 0 outside);
//  - with water, an open face near a shell weighs by its fraction β in the Laplacian and
//    the divergence (face_apertures.hpp);
//  - a flood fill over the cells through the non-Neumann faces finds the fluid regions;
//    a region with no Dirichlet face (enclosed: a pocket, a sealed side) gets the
//    compatibility correction of §4.3 [Peyret and Taylor 1983]: its net boundary flux is
//    spread uniformly over its boundary faces; regions are corrected smallest first, and
//    faces shared with an already corrected region are left alone so that it stays
//    compatible (a pocket corrects the faces it shares with its surroundings, the
//    surroundings then correct their walls);
//  - all regions are solved together (the Laplacian is block diagonal over them; each
//    enclosed region's right-hand side has its mean removed, making the semidefinite
//    system consistent) by one of
//      PCG with a multigrid V-cycle (McAdams, Sifakis & Teran 2010) on the matrix-free
//      7-point operator (linear::GridLaplacian, face weights 1 − Neumann flag), with each
//      enclosed region's constant projected out of the preconditioned residual;
//      PCG with MIC(0) (linear::PcgMic0Solver) on the same operator filled as CSR;
//      a CHOLMOD factorisation (linear::CholmodSolver; one diagonal entry per enclosed
//      region raised by 1, exact for a consistent right-hand side), the reference.
// Unknowns are the scaled pressures p' = p Δt / Δx, so the system is the graph Laplacian
// of the fluid cells, A p' = −Σ_faces u*·n (per cell), and u_f = u*_f − (p'_+ − p'_−).
//
// With water (a FreeSurface) only the cells whose centre has φ <= 0 are unknowns; air
// cells are Dirichlet p = 0 (§4.3). A face between a liquid cell i and an air cell j sees
// the surface at the fraction θ = φ_i / (φ_i − φ_j) of the way (ghost fluid, Gibou et al.
// 2002; Enright et al. 2003: second order), or at j's centre (θ = 1, first order): it
// adds 1/θ to i's diagonal (GridLaplacian::dirichlet) and its velocity is corrected by
// p'_i / θ. Faces between two air cells are left alone (the velocity extrapolation of
// §4.4 fills them); a liquid region with no face to air is enclosed as above. The solve
// runs on the liquid's bounding box only, so its cost follows the water.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/pressure/cut_cell_system.hpp"
#include "shellflow/grid_fluid/pressure/face_apertures.hpp"
#include "shellflow/grid_fluid/pressure/fluid_regions.hpp"
#include "shellflow/linear/constant_null_space.hpp"
#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/multigrid_preconditioner.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"

namespace shellflow::grid_fluid {

enum class PressureSolver { Pcg, Cholmod };
/// Preconditioner of PressureSolver::Pcg.
enum class PressurePreconditioner { Multigrid, Mic0 };

struct ProjectionSettings {
  PressureSolver solver = PressureSolver::Pcg;
  PressurePreconditioner preconditioner = PressurePreconditioner::Multigrid;
  /// Relative residual |b − A p| / |b| of each region's solve; tightened so that the
  /// largest cell divergence after projection is also <= tolerance × max|u*|.
  double tolerance = 1e-6;
  int max_iterations = 2000;
};

/// The liquid of a water scene as the projection sees it.
struct FreeSurface {
  std::span<const double> cell_phi;  ///< φ at each cell centre (φ <= 0: liquid)
  bool ghost_fluid = true;           ///< second-order θ; false: first order (θ = 1)
  /// Smallest θ: a surface closer to the liquid cell's centre counts as this far (keeps
  /// 1/θ, the largest diagonal entry, at 1e3; PhysBAM clamps likewise).
  static constexpr double kMinTheta = 1e-3;
};

/// 1/θ of the face between liquid cell `liquid` and air cell `air`: θ = φ_l / (φ_l − φ_a)
/// clamped to [kMinTheta, 1] (ghost fluid), or 1 (first order).
double free_surface_inverse_theta(const FreeSurface& surface, std::int64_t liquid,
                                  std::int64_t air);

struct ProjectionStats {
  int regions = 0;                 ///< connected fluid regions
  int enclosed_regions = 0;        ///< regions without a Dirichlet face (compatibility corrected)
  int iterations = 0;              ///< PCG iterations, summed over the solves (refinement passes)
  int max_region_iterations = 0;   ///< PCG iterations of the longest single solve
  double relative_residual = 0.0;  ///< largest over the solves
  bool converged = true;
  std::int64_t shell_neumann_faces = 0;  ///< faces closed by a shell (Fig. 5)
  double max_compatibility_flux = 0.0;   ///< largest |net boundary flux| corrected [m^3/s / dx^2]
  /// max over cells |Σ u·n| / max|u| after projection (= |∇·u| Δx / max|u|).
  double max_relative_divergence = 0.0;
  std::int64_t liquid_cells = 0;  ///< pressure unknowns of a water scene (0 for smoke)
  /// Cells of the solve: the liquid's bounding box (water), every cell (smoke).
  std::int64_t solve_cells = 0;
};

/// The work vectors of a pressure solve (CG's and the V-cycle's), which the §5.1 coupling
/// solve and the projection share: they run one after the other within a step, and each
/// needs them only while it runs (Fig. 2's size: 130 MB and 56 MB).
struct SolveScratch {
  std::shared_ptr<linear::PcgWorkspace> pcg = std::make_shared<linear::PcgWorkspace>();
  std::shared_ptr<linear::MultigridScratch> multigrid =
      std::make_shared<linear::MultigridScratch>();
};

class PressureProjection {
 public:
  PressureProjection(const grid::UniformGrid& grid, ProjectionSettings settings,
                     SolveScratch scratch = {});

  const ProjectionSettings& settings() const { return m_settings; }
  /// The work vectors, for a solve that runs beside this one (never at the same time).
  const SolveScratch& scratch() const { return m_scratch; }

  /// Projects `mac` in place. `band` (may be null without shells) lists the faces where
  /// rays are cast. `mac.pressure()` receives p [Pa/(kg/m^3)]. `surface`: the liquid of
  /// a water scene (null: smoke, every cell is fluid).
  ProjectionStats project(MacGrid& mac, double dt, const DomainBoundary& boundary,
                          const ShellGeometry& shells, const geometry::ShellBand* band,
                          const FreeSurface* surface = nullptr);

  /// §4.3 on cut cells (docs/cut-cells.md): every part of a cell the shells cut is an unknown
  /// (CutCellSystem over the whole grid; each singular component's constant projected out),
  /// the faces and `fragments` updated, refined like project() until the parts' largest
  /// divergence is within the tolerance. Leaves what the extrapolation reads as project()
  /// does: neumann() (walls 1; a split face none of whose fragments joins its two cells'
  /// slots 2, its velocity the shells' there), fluid_cell() (the liquid slots), no
  /// apertures; the slots' pressure in `mac`. Its stats count no regions (none are labelled).
  /// `shell_flux`: per part, the moving shells' flux out of it (CutCellSystem::build).
  ProjectionStats project_parts(MacGrid& mac, FragmentVelocities& fragments, double dt,
                                const DomainBoundary& boundary, const ShellGeometry& shells,
                                const CellParts& parts, const CutCellSystem::Liquid& water,
                                std::span<const Eigen::Vector3d> shell_flux = {});

  /// Per cell: 1 where the last projection had a pressure unknown (liquid or smoke).
  bool fluid_cell(std::int64_t cell) const { return m_regions.region[cell] >= 0; }

  /// Neumann flags of the last projection for face family `axis`: 1 a wall's, an inflow
  /// side's or an emitter's face, 2 a face a shell closes (Fig. 5), 0 none.
  const std::vector<std::uint8_t>& neumann(int axis) const { return m_neumann[axis]; }
  /// The face fractions near shells the last projection balanced (none without shells).
  const FaceApertures& apertures() const { return m_apertures; }
  /// Region id of each cell in the last projection.
  const std::vector<int>& region() const { return m_regions.region; }
  /// Scaled pressures p' = p Δt / Δx of the last projection (the next initial guess; part
  /// of the solver state for save/restore).
  Eigen::VectorXd& scaled_pressure() { return m_scaled; }
  const Eigen::VectorXd& scaled_pressure() const { return m_scaled; }
  /// Whether region r has no Dirichlet face.
  bool enclosed(int r) const { return m_regions.enclosed[r] != 0; }

 private:
  void mark_neumann(MacGrid& mac, const DomainBoundary& boundary, const ShellGeometry& shells,
                    const geometry::ShellBand* band, ProjectionStats& stats);
  /// `shell_faces`: whether any face is closed by a shell (without, one region).
  void correct_compatibility(MacGrid& mac, ProjectionStats& stats);
  /// The cells the solve runs on (m_box_lo, m_box_cells; sizes m_laplacian).
  void find_solve_box();
  /// Face weights of the Laplacian (1 − Neumann flag) and the enclosed groups.
  void build_operator();
  /// One solve of A p' = b for the current face velocities into m_scaled (warm start:
  /// m_scaled on entry). `scale` = max|u*|.
  void solve(const MacGrid& mac, double scale, ProjectionStats& stats);

  void apply_pressure(MacGrid& mac) const;
  /// 1/θ of the face between liquid cell `liquid` and air cell `air` (FreeSurface).
  double inverse_theta(std::int64_t liquid, std::int64_t air) const;
  bool air(std::int64_t cell) const { return m_surface != nullptr && m_regions.region[cell] < 0; }
  /// flux[c] = Σ over the six faces of cell c of u·n (= ∇·u Δx) [m/s], a face of fraction
  /// β counted as β u + (1 − β) u_shell (Batty et al. 2007); 0 in a sealed cell, whose
  /// divergence a source sets (m_regions of this projection).
  void cell_fluxes(const MacGrid& mac, Eigen::VectorXd& flux) const;
  /// max over cells |Σ u·n| (in m_flux's storage; m_b's on a whole-grid box, where the
  /// right-hand side is spent by then and m_flux is not used).
  double max_cell_divergence(const MacGrid& mac);
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
  FluidRegions m_regions;
  Eigen::VectorXd m_scaled;           ///< p' = p Δt / Δx, kept as the next initial guess
  linear::GridLaplacian m_laplacian;  ///< on the solve box
  Eigen::Vector3i m_box_lo = Eigen::Vector3i::Zero();
  /// Grid cell of each unknown (box order); empty when the box is the whole grid (smoke,
  /// and water that fills its bounding box of the grid): unknown u is cell u.
  std::vector<std::int64_t> m_box_cells;
  std::int64_t box_cell(std::int64_t u) const { return m_box_cells.empty() ? u : m_box_cells[u]; }
  linear::ConstantNullSpace m_null_space;  ///< constants of the enclosed regions
  int m_enclosed_count = 0;
  std::vector<int> m_first_enclosed_cell;  ///< per enclosed group (CHOLMOD's pinned cell)
  linear::MultigridPreconditioner m_multigrid;
  SolveScratch m_scratch;                  ///< kept between solves
  Eigen::VectorXd m_flux, m_b, m_x;        ///< solve()'s, likewise (m_flux, m_x: sub-boxes only)
  linear::SparseMatrix m_matrix;           ///< CSR form for MIC(0) and CHOLMOD
  const FreeSurface* m_surface = nullptr;  ///< during project() of a water scene
  std::vector<std::uint8_t> m_liquid;      ///< per cell, water scenes only
  FaceApertures m_apertures;               ///< water among shells: the faces' fractions
  CutCellSystem m_parts_system;            ///< project_parts()'s
};

}  // namespace shellflow::grid_fluid
