#pragma once
// Liquid: the water of a grid_fluid scene and its phases of the §6 step (§4.4,
// Guendelman et al. 2005), called by GridFluid in this order:
//   advect()       φ^n → φ* along the velocity's semi-Lagrangian rays (§4.4.1)
//   add_sources()  emitters union their shapes into φ and hold their faces
//   refill()       cells swept by the shells n → n+1 (and those whose stencil saw no
//                  visible sample) take valid values (§3)
//   reinitialize() particle paths against the shells moving n → n+1, the particles' correction of
//                  φ, fast marching to a signed distance against the shells at n+1, the
//                  correction again, radii, and every few frames a reseeding (§4.4.2)
//   surface()      the liquid cells and ghost-fluid data for the projection (§4.3)
//   extrapolate()  after the projection: face velocities across the surface (§4.4)
// A smoke scene has no Liquid (no level set is built).

#include <array>
#include <chrono>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/pressure/pressure_projection.hpp"
#include "shellflow/grid_fluid/water/boundary_phi.hpp"
#include "shellflow/grid_fluid/water/fast_marching.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/level_set_advector.hpp"
#include "shellflow/grid_fluid/water/particle_level_set.hpp"
#include "shellflow/grid_fluid/water/velocity_extrapolation.hpp"
#include "shellflow/grid_fluid/water/volume_budget.hpp"
#include "shellflow/grid_fluid/water/volume_fraction.hpp"
#include "shellflow/grid_fluid/water/water_source.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

/// What the liquid's phases did in the last step, with their wall times [s].
struct LiquidStats {
  FastMarchingStats reinitialization;
  ExtrapolationStats extrapolation;
  std::int64_t invalid_cells = 0;  ///< φ samples refilled (§3, §4.4.1)
  std::int64_t source_nodes = 0;
  ParticleStats particles;
  double t_level_set = 0.0;  ///< advection, sources and refill of φ
  double t_reinitialize = 0.0;
  double t_extrapolate = 0.0;
};

class Liquid {
 public:
  /// The "water" block of the scene (schema()); `up` the pools' up direction, `fps` the
  /// scene's frame rate (the particles' reseeding), `boundary` the domain's sides (walls,
  /// open and inflow sides), `gravity` what the spray falls under.
  Liquid(const nlohmann::json& params, const grid::UniformGrid& grid, const Eigen::Vector3d& up,
         double fps, const DomainBoundary& boundary = DomainBoundary(),
         const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero());
  static sdk::Schema schema();

  const LevelSet& level_set() const { return m_level_set; }
  LevelSet& level_set() { return m_level_set; }
  const LiquidStats& stats() const { return m_stats; }
  const ParticleLevelSet& particles() const { return m_particles; }
  /// Whether each part of a cell the shells cut is its own unknown ("cut_cells").
  bool cut_cells() const { return m_parts_on; }
  /// The water fraction per cell ("volume_fraction"; not enabled() when off).
  const VolumeFraction& fraction() const { return m_fraction; }
  VolumeFraction& fraction() { return m_fraction; }
  /// The velocities the particles move with, on φ's lattice: the centres' means of the
  /// faces of `mac` (computed now).
  const NodeFields& particle_velocity(const MacGrid& mac);
  ParticleLevelSet& particles() { return m_particles; }
  const std::vector<WaterSource>& sources() const { return m_sources; }
  /// The volume water_volume_change counts from [m^3]: the scene's water measured by
  /// volume() against the shells of the first step (before that, without shells).
  double initial_volume() const { return m_initial_volume; }
  bool initial_volume_measured() const { return m_initial_volume_measured; }
  void measure_initial_volume(const ShellGeometry* shells, const geometry::ShellBand* band) {
    set_initial_volume(volume(shells, band));
  }
  /// The scene's water among the shells of the first step: its level set as built, made a
  /// distance again by a march that sees them. The march at construction sees none, and
  /// took a shape's face lying on a shell (water standing in a cup, a layer on a shelf) for
  /// a surface, thinning the water there.
  void settle_among_shells(const ShellGeometry& shells, const geometry::ShellBand* band);
  /// A restored run's: the volume the run counted from.
  void set_initial_volume(double volume) {
    m_initial_volume = volume;
    m_initial_volume_measured = true;
    std::vector<double>().swap(m_built);  // a restored run settled long ago
  }
  /// What the emitters added and the open sides let out since the start.
  const VolumeBudget& budget() const { return m_budget; }
  /// A restored run's.
  void set_budget(const VolumeBudget& budget) { m_budget = budget; }
  /// Where the drift arose ("volume_by_phase"; null when off).
  const PhaseDrift* phase_drift() const { return m_by_phase ? &m_phase_drift : nullptr; }
  /// A restored run's, and the volume its last step ended with.
  void set_phase_drift(const PhaseDrift& drift, double last_end) {
    m_phase_drift = drift;
    m_phase_end = last_end;
  }
  double phase_end() const { return m_phase_end; }
  /// φ is advected by MacCormack's corrected step ("advection": "maccormack").
  bool maccormack() const { return m_advector.maccormack(); }

  /// The nodes whose advected velocity the next projection can read (one byte per node),
  /// from φ^n before advect(): a face next to a liquid cell of step n+1 has its nodes
  /// within √3Δx of the water then, so within dt·max_speed + √3Δx of it now; one Δx more
  /// for the ring averaging and reinitialisation, and every node about an emitter that is
  /// on at t. Velocities elsewhere are extrapolated or zero (§4.4): not worth advecting.
  std::span<const std::uint8_t> velocity_nodes(double t, double dt, double max_speed);
  /// φ along the velocity's rays, the particles along their second-order paths: the cell
  /// centres' mean of the faces of `mac` (the faces' divergence-free field, whose wall faces
  /// hold the walls' normal velocity). `t`: the time at the start of the step (the emitters
  /// on then, whose flow the budget counts). `max_speed` [m/s]: no face of `mac` is faster
  /// (φ is traced only within a band about the water that it sets).
  void advect(double t, const MacGrid& mac, double dt, double max_speed,
              const ShellGeometry& shells, const geometry::ShellBand* band);
  void add_sources(double t, DomainBoundary& boundary);
  /// `swept`: the cells the shells swept n → n+1 (SweptRefill::swept_cells); may be empty.
  /// `shells_n`, `shells`: the shells at the start and the end of the step.
  void refill(std::span<const std::int64_t> swept, double dt, const ShellGeometry& shells_n,
              const ShellGeometry& shells);
  /// `shells_n`, `shells`: the shells at the start and the end of the step; `t_end`: the
  /// time at the end of the step.
  void reinitialize(const ShellGeometry& shells_n, const ShellGeometry& shells,
                    const geometry::ShellBand* band, double t_end);
  /// The projection's view of the liquid (valid until the next advect()): φ at the cell
  /// centres.
  const FreeSurface& surface();
  /// The view the last surface() gave (its cell_phi empty before the first).
  const FreeSurface& last_surface() const { return m_surface; }
  /// The water's volume [m^3] (LevelSet::volume), where `shells` cut a cell of `band`
  /// each side counted with its own φ (sampled where no one plane parts the sides);
  /// without shells or band, LevelSet::volume().
  double volume(const ShellGeometry* shells, const geometry::ShellBand* band) const;
  void extrapolate(MacGrid& mac, const PressureProjection& projection, const ShellGeometry& shells,
                   const geometry::ShellBand* band);

 private:
  /// At the first step, φ just set to m_built: water nodes next to a shell whose φ is their
  /// distance to it (a face of the scene's shape on the shell) made deep water for the march
  /// to set, or, next to a node across the surface, given the distance that node implies.
  void forget_faces_on_shells(const ShellGeometry& shells, const geometry::ShellBand& band);
  /// The water fraction of a cell that one plane does not part (two shells or a shell's
  /// edge cut it: volume()), sampled on a 4×4×4 lattice of its points, each read from the
  /// corners it sees; `own`, the cell's corners, if none sees any.
  double sampled_cell_fraction(const Eigen::Vector3i& cell, const std::array<double, 8>& own,
                               const ShellGeometry& shells) const;
  /// refill(): the cells the shells swept take φ^n where their water came from, moving with
  /// the centres' velocities advect() traced with; those that cannot are added to m_invalid.
  void carry_swept_cells(std::span<const std::int64_t> swept, double dt,
                         const ShellGeometry& shells_n, const ShellGeometry& shells);

  /// The cells a face the shells close bounds (their two sides share one F), in
  /// m_cut_cells: F leaves φ as it is there.
  void mark_cut_cells(const ShellGeometry& shells, const geometry::ShellBand* band);
  /// F fitted to φ settled among `shells` (settle_among_shells()).
  void fit_fraction_among_shells(const ShellGeometry& shells, const geometry::ShellBand* band);
  /// advect()'s part for the water fraction: F over dt, its flows into the budget.
  void advect_fraction(double t, const MacGrid& mac, double dt, double max_speed,
                       const ShellGeometry& shells, const geometry::ShellBand* band);
  /// The MAC cells emitter `s`'s shape may reach.
  grid::IndexBox emitter_cells(const WaterSource& s) const;
  /// The velocity at each cell centre, the mean of its two faces per axis (PhysBAM's
  /// Face_To_Cell_Vector), in `m_centre_velocity` on the centres' lattice: only at the cells
  /// with |φ| <= `within` [m] or within `side_cells` of a side of the domain (the others
  /// keep what they held, and nothing this step reads them).
  void centre_velocities(const MacGrid& mac,
                         double within = std::numeric_limits<double>::infinity(),
                         int side_cells = 0);

  LevelSet m_level_set;
  NodeFields m_centre_velocity;  ///< what φ's rays follow
  VolumeFraction m_fraction;
  bool m_parts_on = false;                     ///< "cut_cells"
  std::vector<grid::IndexBox> m_held_sources;  ///< cells of the emitters on this step
  std::vector<double> m_scratch;  ///< φ* being advected; after advect(), φ^n until refill(); then
                                  ///< fast marching's distances and the volume fraction's scratch
  std::vector<double> m_swept_value;  ///< refill(): their φ^n carried with the shell
  std::vector<std::uint8_t> m_cut_cells;    ///< mark_cut_cells()'
  std::vector<std::int64_t> m_cut_list;     ///< those, as a list
  std::vector<double> m_built;    ///< φ as the scene built it, until the first step
  size_t m_marched_hash = 0;      ///< of φ as marched at construction
  LevelSetAdvector m_advector;
  FastMarching m_fast_marching;
  VelocityExtrapolation m_extrapolation;
  ParticleLevelSet m_particles;
  std::vector<WaterSource> m_sources;
  std::vector<grid::IndexBox> m_emitting;  ///< node boxes of the emitters that set φ this step
  double m_extrapolation_width = 0.0;      ///< [m]
  std::vector<std::int64_t> m_invalid;
  std::vector<std::uint8_t> m_valid;
  std::array<bool, 6> m_walls{};  ///< sides of the domain that are walls
  std::array<bool, 6> m_open{};   ///< sides of the domain that are open (outflow)
  BoundaryPhi m_boundary_phi;     ///< φ beyond the open and inflow sides, advect()
  VolumeBudget m_budget;
  std::vector<std::uint8_t> m_emitter_filling;  ///< per emitter, this step: apply() counts
  std::vector<double> m_held_flow;  ///< per emitter, emitter_held_flow() once known (else NaN)
  // "volume_by_phase": the sums, the volume at the last phase's end (NaN before the first
  // step), and this step's shells at n and band (set by advect()).
  bool m_by_phase = false;
  PhaseDrift m_phase_drift;
  double m_phase_end = std::numeric_limits<double>::quiet_NaN();
  VolumeBudget m_phase_budget;  ///< the budget at the step's start
  const ShellGeometry* m_phase_shells_n = nullptr;
  const geometry::ShellBand* m_phase_band = nullptr;
  /// Measures the water after a phase, adds its change to `phase`.
  void end_phase(double& phase, const ShellGeometry* shells);
  FreeSurface m_surface;
  std::array<std::vector<std::uint8_t>, 3> m_known;
  std::vector<std::uint8_t> m_velocity_nodes;
  std::array<std::vector<std::uint8_t>, 2> m_node_flags;  ///< velocity_nodes()' cells, passes
  double m_initial_volume = 0.0;
  bool m_initial_volume_measured = false;
  LiquidStats m_stats;
};

}  // namespace shellflow::grid_fluid
