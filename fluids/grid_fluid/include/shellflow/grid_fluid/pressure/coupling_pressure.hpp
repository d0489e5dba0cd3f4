#pragma once
// CouplingPressure: the forces of the fluid on two-way coupled shells (§5.1, eq. (5)–(6),
// Guendelman et al. 2005).
//
//  1. A face whose cell-centre segment meets a two-way shell (Fig. 5) takes the shell's
//     velocity and the density m/V of the shell: m = Δx² σ (face area × surface
//     density), V = Δx³, so ρ_face = σ/Δx. Every other face keeps the fluid density ρ.
//     Faces closed by a kinematic (one-way) shell, walls and inflow faces stay Neumann:
//     nothing the fluid does moves them.
//  2. The variable-coefficient Poisson equation ∇·(∇p/ρ) = ∇·u*/Δt (eq. (6)) is solved
//     without Neumann faces across two-way shells. Unknowns are q = p Δt/(ρ Δx); a face
//     of coefficient β = ρ/ρ_face updates as u −= β (q₊ − q₋) (eq. (5)), so the matrix
//     is the β-weighted graph Laplacian of the cells (open domain faces: q = 0 outside).
//     Enclosed regions get the mean of their right-hand side removed (compatibility).
//     CG with the multigrid V-cycle of McAdams et al. 2010, whose coarse levels average
//     the face weights, so a heavy or light shell face is just a weaker or stronger face.
//  3. The pressure jump p₊ − p₋ on each shell face goes to the four nodes of that face
//     (average of the adjacent shell faces, per axis), is spread to the nodes around the
//     shell by Gauss–Jacobi averaging (geometry::GaussJacobiRefill), and is interpolated
//     trilinearly to each triangle's barycentre: a vector D of jumps along x, y, z.
//  4. The jump across the triangle is [p] = D·n / |n|₁ and its force is −[p] A n.
//     The paper takes D·n; on a sheet inclined to the grid every cut axis sees the full
//     jump (D_a = [p] sign n_a), so D·n = [p] |n|₁ — up to √3 too large. Dividing by
//     |n|₁ makes the force independent of the sheet's orientation to the grid and equal
//     to the paper's for grid-aligned sheets.
// The fluid's velocities are not changed: eq. (5) only measures the force (§5.1).
//
// A two-way shell that is one rigid body (ShellSurface::rigid) does not take σ/Δx on its
// faces: the body moves as one in the solve (rigid_shell_coupling.hpp), its faces leave
// the Laplacian and its inverse mass and inertia enter the operator. Steps 3–4 are the same.
//
// With water (a FreeSurface, as the projection sees it) the faces near shells weigh by
// their fractions, as in the projection (face_apertures.hpp), and only the liquid cells
// are unknowns: air cells hold p = 0, a liquid cell's face to an air cell is a Dirichlet
// conductance (its weight, 1 or β, times 1/θ of the ghost fluid rule; θ = 1 across a
// shell, where φ of the far side says nothing of this side's surface), and a liquid
// region with no face to air is enclosed. A shell face with air on both sides has no
// jump: shells and the parts of shells in air feel no pressure (§5.1 with a free surface),
// and a partly submerged shell feels the jump only below the water. Water has a
// hydrostatic gradient ρg, so the jump is taken at the shell, not between the cell
// centres: each side's pressure is extrapolated to where the shell cuts the segment with
// its one-sided slope (else a submerged sheet would feel the buoyancy of a Δx-thick slab
// and a hull ρ g s too much, s its distance to the cell centre below: a draft off by s).

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid/sparse_samples.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/pressure/face_apertures.hpp"
#include "shellflow/grid_fluid/pressure/fluid_regions.hpp"
#include "shellflow/grid_fluid/pressure/pressure_projection.hpp"
#include "shellflow/grid_fluid/pressure/rigid_shell_coupling.hpp"
#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/multigrid_preconditioner.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::grid_fluid {

struct CouplingSettings {
  double fluid_density = 1.0;  ///< ρ [kg/m^3]
  double tolerance = 1e-6;     ///< PCG relative residual
  int max_iterations = 2000;
  /// Gauss–Jacobi layers the face jumps spread from the shell's faces (step 3).
  int spread_layers = 4;
};

struct CouplingStats {
  std::int64_t coupled_faces = 0;    ///< faces carrying a two-way shell's mass
  std::int64_t rigid_faces = 0;      ///< of those, faces of rigid shells moved as one body
  std::int64_t kinematic_faces = 0;  ///< faces closed by a one-way shell (Neumann)
  int iterations = 0;
  double relative_residual = 0.0;
  bool converged = true;
  double max_pressure_jump = 0.0;           ///< max |p₊ − p₋| over the shell faces [Pa]
  std::int64_t triangles_without_jump = 0;  ///< triangles with no jump data near them
  Eigen::Vector3d total_force = Eigen::Vector3d::Zero();  ///< Σ over all triangles [N]
};

class CouplingPressure {
 public:
  /// `scratch`: the work vectors, shared with the projection.
  CouplingPressure(const grid::UniformGrid& grid, CouplingSettings settings,
                   SolveScratch scratch = {});

  const CouplingSettings& settings() const { return m_settings; }

  /// Forces [N] on the triangles of the two-way shells of `set` (the shells that
  /// `shells` was built from, same order) from u* in `mac`, which is left unchanged.
  /// `forces[s]` must hold set[s].triangle_count() rows; rows of one-way shells are
  /// left as they are. `band` labels the faces near the shells (rays only there).
  /// `surface`: the liquid of a water scene (null: smoke, every cell is fluid).
  CouplingStats compute(const MacGrid& mac, double dt, const DomainBoundary& boundary,
                        const ShellGeometry& shells, const geometry::ShellBand& band,
                        sdk::ShellSet set, std::span<sdk::TriangleVectors> forces,
                        const FreeSurface* surface = nullptr);

  /// q = p Δt/(ρ Δx) of the last solve (the next initial guess; saved with the fluid).
  Eigen::VectorXd& scaled_pressure() { return m_scaled; }
  const Eigen::VectorXd& scaled_pressure() const { return m_scaled; }

 private:
  /// A face that the shells override: its velocity, and its coefficient β (0: Neumann).
  struct ShellFace {
    int axis;
    std::int64_t face;
    double velocity;
    double beta;
    double s;      ///< where the shell cuts the segment between the cell centres, 0 at the − cell
    int body;      ///< a rigid shell's face: its index in m_bodies (β unused); else −1
    int triangle;  ///< of the shell, where the segment meets it
    /// A rigid shell's face: J_fᵀ and the flux it carries per Δx² (water: [N_f; M_f]/Δx²
    /// and Φ_f/Δx² of the pieces of shell it stands for, rigid_face_areas.hpp; smoke:
    /// [e_a; r × e_a] at its centre and the shell's velocity along a there).
    BodyVector row = BodyVector::Zero();
    double flux = 0.0;
    bool two_way() const { return beta > 0.0 || body >= 0; }
  };
  void classify_faces(const DomainBoundary& boundary, const ShellGeometry& shells,
                      const geometry::ShellBand& band, sdk::ShellSet set, CouplingStats& stats);
  /// Each rigid body's faces get their rows J_f and fluxes (ShellFace::row).
  void assign_rigid_face_areas(sdk::ShellSet set);
  Eigen::VectorXd right_hand_side(const MacGrid& mac) const;
  void solve(Eigen::VectorXd& b, double dt, const DomainBoundary& boundary, CouplingStats& stats);
  /// The fluid regions and which are enclosed (their constants: the operator's null space).
  void label_regions(const DomainBoundary& boundary, const CouplingStats& stats);
  /// The jump [q] of every shell face (m_jumps) and the rigid bodies' faces (m_bodies).
  void build_jumps();
  /// Water: faces touching air leave the Laplacian, the liquid cell's side becomes a
  /// Dirichlet conductance (weight × 1/θ), and the air rows are emptied (b = 0, guess q = 0).
  void add_free_surface(Eigen::VectorXd& b);
  /// Water with rigid bodies: a liquid cell that no face of L reaches (a sliver of water
  /// sealed in a hull's corner by its faces, which the body alone would join) is left out
  /// as air: a cell the V-cycle cannot see stalled CG, and its volume is below a cell's.
  void drop_sealed_cells(Eigen::VectorXd& b);
  bool air(std::int64_t cell) const { return m_surface != nullptr && m_liquid[cell] == 0; }
  /// The cells a shell face lies between: {below it along its axis, above it}.
  std::pair<std::int64_t, std::int64_t> cells_of(const ShellFace& sf) const;
  /// Water: whether a two-way shell face has water on either side (else no force anywhere).
  bool water_at_two_way_faces() const;
  void jumps_to_nodes(double to_pressure, CouplingStats& stats);
  /// Water: adds `sign` × q of `cell` extrapolated by `reach` cells (its distance to the
  /// shell) away from its neighbour `cell − step·e_axis`, with the one-sided slope through
  /// that neighbour (0 at the free surface's ghost point for air; no slope across a wall or
  /// shell), to `jump`. Air cells add nothing (q = 0).
  void add_side_at_shell(FaceJump& jump, std::int64_t cell, int axis, int step, double reach,
                         double sign) const;
  void forces_on_triangles(sdk::ShellSet set, std::span<sdk::TriangleVectors> forces,
                           CouplingStats& stats);
  /// A rigid body's triangle forces, corrected to carry its solve's wrench exactly (a
  /// force per area plus a torque per area moment, about the triangles' area centroid).
  static void match_wrench(const RigidShellFaces& body, const BodyVector& wrench,
                           sdk::TriangleVectors& out);

  grid::UniformGrid m_grid;
  CouplingSettings m_settings;
  std::array<std::vector<std::uint8_t>, 3> m_closed;  ///< Neumann faces
  std::vector<ShellFace> m_shell_faces;
  std::vector<FaceJump> m_jumps;          ///< per shell face: [q] at the shell
  std::vector<int> m_body_of_shell;       ///< per shell of the set: index in m_bodies, or −1
  std::vector<BodyVector> m_body_wrench;  ///< per body: ρ Δx³/Δt K q [N; N m]
  std::vector<RigidShellFaces> m_bodies;
  const FreeSurface* m_surface = nullptr;                   ///< during compute() of a water scene
  FaceApertures m_apertures;  ///< water: the fractions of faces near shells, as the projection
  std::vector<std::uint8_t> m_liquid;                       ///< per cell, water scenes only
  std::array<std::vector<std::uint8_t>, 3> m_two_way_face;  ///< water: faces of m_shell_faces
  FluidRegions m_regions;
  linear::GridLaplacian m_laplacian;            ///< face weights β
  linear::MultigridPreconditioner m_multigrid;  ///< McAdams et al. 2010 V-cycle
  SolveScratch m_scratch;                       ///< kept between solves
  Eigen::VectorXd m_scaled;
  // Step 3: per axis, the jump on the nodes and its validity; only touched entries are
  // non-zero between calls.
  /// Per node near a two-way shell: the jump from the faces of each axis about it.
  grid::SparseSamples<Eigen::Vector3d> m_node_jump;
  std::array<std::vector<std::uint8_t>, 3> m_node_valid;
  /// Step 3–4: trilinear stencil of each two-way triangle's barycentre.
  struct TriangleStencil {
    Eigen::Vector3i lower;  ///< lowest node of the cell
    Eigen::Vector3d t;      ///< weights along x, y, z in [0, 1]
  };
  std::vector<TriangleStencil> m_stencils;
};

}  // namespace shellflow::grid_fluid
