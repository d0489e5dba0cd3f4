#pragma once
// GridFluid: the "grid_fluid" fluid plugin — smoke or water on a uniform MAC grid that
// never leaks through thin shells (§3, §4, Guendelman et al. 2005). A "water" block makes
// it a water scene (Liquid: level set, fast marching, extrapolation, free surface); without
// one it is smoke (density, temperature, buoyancy, vorticity confinement).
//
// One step, as the §6 coupling loop calls it:
//   advect(t, Δt, shells^n, shells^{n+1})
//     1. faces → nodes with visibility (§4.2; done at the end of the last projection)
//     2. semi-Lagrangian advection of velocity, density, temperature on the nodes with the
//        doubled wedge and the 8 secondary rays (§4.1); fast path outside the shell band
//        water: φ along the same rays (§4.4.1)
//     3. smoke: sources, buoyancy, vorticity confinement on the nodes (§4.1);
//        water: gravity on the nodes, emitters into φ
//     4. shells move n → n+1: swept nodes invalidated and refilled (§3); water: φ
//        refilled and reinitialised by fast marching against the shells at n+1 (§4.4.1)
//     5. increments u* − u^n averaged back to the persistent faces with visibility (§4.2)
//   coupling_forces(Δt, shells^{n+1})
//     §5.1 eq. (5)–(6): faces cut by two-way shells take the shell's velocity and density
//     σ/Δx, the variable-coefficient Poisson equation is solved without Neumann faces
//     there, and the pressure jumps become per-triangle forces (CouplingPressure);
//     skipped when no shell receives fluid forces
//   project(Δt, shells^{n+1}, v_eff)
//     Neumann faces across shells with the effective velocity, flood fill, compatibility
//     per enclosed region, PCG/MIC(0) or CHOLMOD per region (§4.3); water: air cells
//     Dirichlet with the ghost fluid method, then velocities extrapolated across the
//     surface (§4.4); then faces → nodes.
// With a "prescribed_velocity" (water only) the velocity is not solved for: faces and
// nodes are sampled from the analytic field, the nodes at the middle of each step, and φ
// and the particles are carried by it (steps 1, 3, 5 and the projection are skipped): the
// transport tests of the level-set literature (Zalesak's sphere, LeVeque's deformation).

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/fluid_probes.hpp"
#include "shellflow/grid_fluid/mac/analytic_velocity.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/face_node_transfer.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/semi_lagrangian_advector.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/mac/swept_refill.hpp"
#include "shellflow/grid_fluid/pressure/coupling_pressure.hpp"
#include "shellflow/grid_fluid/pressure/pressure_projection.hpp"
#include "shellflow/grid_fluid/smoke/smoke_forces.hpp"
#include "shellflow/grid_fluid/smoke/smoke_source.hpp"
#include "shellflow/grid_fluid/water/cut_cell_water.hpp"
#include "shellflow/grid_fluid/water/liquid.hpp"
#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

/// What the last step did, for report() and tests.
struct StepStats {
  ProjectionStats projection;
  CouplingStats coupling;
  SweptRefillStats refill;
  std::int64_t band_nodes = 0;
  std::int64_t source_nodes = 0;
  double max_force = 0.0;
};

class GridFluid final : public sdk::FluidSolver {
 public:
  static sdk::Schema schema();
  /// `params` validated against schema(). Throws ConfigError for values the schema
  /// cannot check (an empty domain box, an inflow pointing out).
  GridFluid(const nlohmann::json& params, const sdk::Context& context);

  double stable_dt(double cfl) const override;
  /// The fastest face, or fragment of a cut cell's face [m/s].
  double max_flow_speed() const;
  void start(double dt, sdk::ShellSet shells,
             std::span<const sdk::Positions> effective_velocity) override;
  void advect(double t, double dt, sdk::ShellSet shells_n, sdk::ShellSet shells_np1) override;
  /// §5.1: forces on the triangles of the shells that receive fluid forces, from u*
  /// (CouplingPressure); rows of one-way shells stay as the runtime passed them (zero).
  void coupling_forces(double dt, sdk::ShellSet shells,
                       std::span<sdk::TriangleVectors> triangle_forces) override;
  void project(double dt, sdk::ShellSet shells,
               std::span<const sdk::Positions> effective_velocity) override;
  void save(sdk::StateWriter& out) const override;
  void restore(sdk::StateReader& in) override;
  std::vector<sdk::FieldView> fields() const override;
  /// Water with marker particles: "spray" (the removed water particles, flying; see
  /// ParticleLevelSet), "escaped_water" (water particles outside the water by more than
  /// their radius: drops the level set does not hold, still marker particles),
  /// "water_particles" and "air_particles" (the marker particles of each sign); each with
  /// the node velocity at the particle. Nothing for smoke or without particles.
  std::vector<sdk::ParticleView> particles() const override;
  std::optional<std::string> find_nonfinite() const override;
  void report(sdk::Metrics& out) const override;
  std::vector<sdk::PlanEntry> plan() const override;
  /// The grid's box (max as moved to fit whole cells) and the "boundary" sides.
  std::optional<sdk::DomainView> domain() const override;

  // For tests and benchmarks.
  const grid::UniformGrid& grid() const { return m_mac.grid(); }
  MacGrid& mac() { return m_mac; }
  const MacGrid& mac() const { return m_mac; }
  NodeFields& nodes() { return m_nodes; }
  const NodeFields& nodes() const { return m_nodes; }
  const StepStats& last_step() const { return m_stats; }
  const PressureProjection& projection() const { return m_projection; }
  const DomainBoundary& boundary() const { return m_boundary; }
  double epsilon() const { return m_epsilon; }
  bool temperature_enabled() const { return m_temperature; }
  double fluid_density() const { return m_density; }
  /// Recomputes the node velocities from the faces (§4.2) against `shells` (e.g. after a
  /// test wrote face velocities directly).
  void refresh_nodes(sdk::ShellSet shells);
  /// Σ density Δx^3 over the nodes (smoke "mass").
  double smoke_mass() const;
  /// The water of a water scene (null for smoke).
  const Liquid* liquid() const { return m_liquid.get(); }
  Liquid* liquid() { return m_liquid.get(); }
  /// The water's cut cells (null without /water/cut_cells, or before the first step).
  const CutCellWater* cut_water() const {
    return m_cut_water && m_cut_water->ready() ? m_cut_water.get() : nullptr;
  }

 private:
  /// Logs once for each level of drift the water's `volume` passes against what the scene
  /// holds, `held` (V0 + added − outflow; report() calls it).
  /// report()'s water metrics: volume and its budget, energy, the phases' counts and times.
  void report_water(sdk::Metrics& out) const;
  void warn_of_volume_drift(double volume, double held) const;
  /// Makes `cache` hold `shells` (rebuilds unless the positions match); true when rebuilt.
  bool ensure_geometry(std::unique_ptr<ShellGeometry>& cache, sdk::ShellSet shells) const;
  static std::vector<sdk::Positions> velocities_of(sdk::ShellSet shells);
  /// The §5.1 solver, made on first use (its arrays cost memory only in two-way scenes).
  CouplingPressure& coupling_pressure();
  void build_band(sdk::ShellSet shells_n, sdk::ShellSet shells_np1, double margin);
  /// §4.3–4.4 against `shells` held in `geometry`: the projection with Neumann faces moving
  /// at `boundary_velocity`, the velocities extrapolated across the surface, the nodes
  /// (§4.2) against the shells' own velocities. project() and start() differ only in it.
  void project_against(std::unique_ptr<ShellGeometry>& geometry, double dt, sdk::ShellSet shells,
                       std::span<const sdk::Positions> boundary_velocity);
  /// Step 3 of advect() for water (gravity on the nodes, emitters) and for smoke.
  /// Once, before the water's first step or projection: φ and F settled among `shells`, the
  /// volume water_volume_change counts from measured.
  void settle_water(const ShellGeometry& shells, const geometry::ShellBand* band);
  void advect_water_forces(double t, double dt);
  void add_smoke_forces(double t, double dt, const ShellGeometry& geom_n,
                        const geometry::ShellBand* band);
  /// The prescribed field at time t on the nodes and the faces (exact samples): the faces
  /// carry φ, the nodes are what the writers show.
  void sample_prescribed(double t);

  sdk::Context m_context;
  DomainBoundary m_boundary;
  double m_epsilon = 0.0;
  double m_density = 1.0;  ///< ρ [kg/m^3]
  double m_coupling_tolerance = 1e-4;
  bool m_temperature = false;
  BuoyancyParameters m_buoyancy;
  double m_vorticity = 0.0;
  std::vector<SmokeSource> m_sources;

  MacGrid m_mac;
  NodeFields m_nodes;
  NodeFields m_next;  ///< advect()'s target; after it, the fields at n
  bool m_nodes_current = false;
  double m_time = 0.0;

  FaceNodeTransfer m_transfer;
  SemiLagrangianAdvector m_advector;
  SmokeForces m_forces;
  SweptRefill m_refill;
  PressureProjection m_projection;
  std::unique_ptr<CouplingPressure> m_coupling;  ///< made on the first two-way step
  std::unique_ptr<Liquid> m_liquid;              ///< water scenes only
  std::unique_ptr<CutCellWater> m_cut_water;     ///< water with /water/cut_cells only
  /// The split faces §4.2's transfers read and write (null: none).
  const CutFaces* cut_faces() { return m_cut_water ? m_cut_water->cut_faces() : nullptr; }
  std::optional<AnalyticVelocity> m_prescribed;  ///< "prescribed_velocity": no solve
  std::vector<double> m_initial_phi;             ///< φ at t = 0, with a prescribed velocity
  double m_prescribed_speed = 0.0;               ///< its largest face speed at any time
  FluidProbes m_probes;                          ///< figures for metrics.csv ("probes")
  double m_t_pressure = 0.0;                     ///< wall time of the last projection [s]
  geometry::ShellBand m_band;
  bool m_band_used = false;
  /// The shells at the start of the step; between steps (project() swaps the two), those at
  /// its end, where the water is: what report() and particles() measure against.
  std::unique_ptr<ShellGeometry> m_geometry_n;
  std::unique_ptr<ShellGeometry> m_geometry_np1;
  double m_shell_speed = 0.0;
  StepStats m_stats;
  bool m_logged_coupling = false;
  /// Warnings of the water's volume drift given so far (one per level of kDriftWarnings).
  mutable int m_drift_warnings = 0;
  /// The marker particles gathered for particles() (water, air, escaped water): writers'
  /// copies.
  mutable std::array<ParticleArrays, 3> m_marker_views;
};

}  // namespace shellflow::grid_fluid
