#pragma once
// ParticleLevelSet: marker particles of both signs about the water's surface that give the
// level set back the sub-cell detail it loses in thin films and sharp features (§4.4.2,
// Guendelman et al. 2005; Enright, Fedkiw, Ferziger, Mitchell 2002; Enright, Losasso,
// Fedkiw 2005: first-order semi-Lagrangian φ, second-order particles). Liquid calls, per
// step:
//   advect()   §4.4.2's second-order path: move with the velocity at the particle, sample
//              the velocity there, average, and move from the start with the average; each
//              path is checked against the shells at n (the stationary object). A water
//              particle nearer a shell than its collision distance, or whose forward move
//              met one, has the normal component of its velocity clamped to at least the
//              object's, so it gets no nearer; a water particle stays its collision
//              distance off the domain's walls (or no nearer than it was), as PhysBAM's
//              Adjust_Particle_For_Domain_Boundaries keeps it: a wall node's velocity has
//              no normal part, so one on a wall's plane stayed there and held a film of
//              water on the wall
//   collide()  the paths against the shells moving from n to n+1: the particle's path
//              and each triangle's linear motion are tested together (the relative motion
//              of a point against a moving triangle, geometry/swept_point), so a shell
//              sweeping over a particle is caught as well as a particle crossing a shell.
//              A crossing deletes an air particle; a water particle is put back on the side
//              it started on, its collision distance off the triangle at n+1, and deleted
//              if that corrected path still crosses. Then every water particle nearer a
//              shell than its collision distance (drawn once in [0.1Δx, Δx]) is moved out
//              along the distance gradient to it, or left where it is if the move would
//              cross a shell (§4.4.2) or carry it out of the water by more than its radius
//              (it would be an escaped particle making water in the air)
//   correct()  escaped particles (on the wrong side by more than their radius) rebuild φ
//              at the corners of their cell that they see: water spheres lower φ, air
//              spheres raise it, and of the two the value nearer zero wins (Enright 2002,
//              §3.3); before and after reinitialisation
//   adjust()   radii to s φ(x) clamped to [0.1Δx, 0.5Δx]; particles deeper than the seeding
//              band deleted; air particles escaped by more than 1.5 radii deleted (no
//              bubbles: the pressure keeps none, PhysBAM's water examples drop them too);
//              water particles still more than Δx beyond the surface after the second
//              correction removed from the level set: spray the grid cannot hold (counted
//              as `removed`, and kept as spray drops, below). Water particles nearer than
//              that are kept: a correction leaves φ at an escaped particle near 0.6Δx − r,
//              and removed at 1.5 radii they took sharp features' water with them
//   reseed_if_due()  every `reseed_every` frames: band cells holding fewer than `per_cell`
//              particles get new ones (seeded ignoring the shells, then their sign taken
//              from φ as seen from them, §4.4.2; water ones moved out to their collision
//              distance), cells holding more than twice lose the
//              excess; the cells about an emitter that is on are topped up every step,
//              and the air particles its water now covers are dropped
// Spray (for writers; it never acts on φ or the velocity): a removed water particle
// becomes a ballistic drop with the velocity of its last path and its radius, moved in
// advect() by x += Δt u + ½Δt² g, u += Δt g, and deleted when its path meets a shell at n
// or leaves the domain (advect()) or it is back in water, φ <= 0 as seen from it
// (adjust()): it has landed. Its water is not given back to the level set.
// φ at a particle is read as at a semi-Lagrangian base point (LevelSetAdvector::
// sample_visible), its velocity from the 8 nodes of its cell with the object's velocity
// standing in for nodes it does not see (§4.1). Attributes are flat arrays, one per
// attribute (no per-particle allocation); a particle's random numbers come from its cell
// and the seeding round, so runs are the same on any thread count.

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/geometry/swept_triangle_bvh.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/level_set_advector.hpp"
#include "shellflow/grid_fluid/water/particle_arrays.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::grid_fluid {

/// What the particles did in the last step.
struct ParticleStats {
  std::int64_t negative = 0;           ///< water particles after the step
  std::int64_t positive = 0;           ///< air particles after the step
  std::int64_t escaped = 0;            ///< escaped particles used by the two corrections
  std::int64_t corrected_nodes = 0;    ///< nodes whose φ a correction changed
  std::int64_t deleted_at_shells = 0;  ///< particles whose path crossed a shell, deleted
  std::int64_t kept_off_shells = 0;    ///< water particles moved out to their collision distance
  std::int64_t removed = 0;            ///< water particles removed as escaped (spray)
  std::int64_t reseeded = 0;           ///< particles added by seeding this step
  std::int64_t spray = 0;              ///< spray drops in flight after the step
  std::int64_t landed = 0;             ///< spray drops deleted this step (landed or left)
  double seconds = 0.0;                ///< wall time of the particle phases
};

class ParticleLevelSet {
 public:
  /// The "particles" block of the water (schema()); `domain` the MAC grid, whose cells are
  /// seeded and whose box holds the particles (they move with the velocities at its cell
  /// centres, φ's lattice); `fps` the scene's frame rate; `gravity` [m/s^2] what the spray
  /// falls under.
  ParticleLevelSet(const nlohmann::json& params, const grid::UniformGrid& domain, double fps,
                   const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero());
  static sdk::Schema schema();
  /// The domain's sides that are walls (−x, +x, −y, +y, −z, +z): water particles keep their
  /// collision distance off them as off a shell.
  void set_walls(const std::array<bool, 6>& walls) { m_walls = walls; }

  bool enabled() const { return m_per_cell > 0; }
  std::int64_t size() const { return static_cast<std::int64_t>(m_x.size()); }
  /// Bytes the marker particles' arrays hold (their capacities), spray and the per-node
  /// correction scratch left out.
  std::size_t particle_bytes() const;
  const ParticleStats& stats() const { return m_stats; }
  /// Particle i's position, sign (−1 water, +1 air) and radius.
  Eigen::Vector3d position(std::int64_t i) const { return {m_x[i], m_y[i], m_z[i]}; }
  int sign(std::int64_t i) const { return m_sign[i]; }
  double radius(std::int64_t i) const { return m_radius[i]; }
  /// The distance particle i keeps from shells if it is water (§4.4.2: drawn once in
  /// [0.1Δx, Δx]).
  double collision_distance(std::int64_t i) const { return m_collision[i]; }
  /// The spray drops in flight (see the file's comment).
  const ParticleArrays& spray() const { return m_spray; }
  /// The particles of sign `sign` (−1 water, +1 air) with the node velocity at each (the
  /// object's velocity standing in for nodes a particle does not see, rays cast only for
  /// particles in `band`; may be null), into `out` (replaced). With `escaped_from`, only
  /// those on the wrong side of its surface by more than their radius (escaped, as
  /// correct() finds them): water the level set does not hold.
  void gather(int sign, const NodeFields& velocity, const ShellGeometry& shells,
              const geometry::ShellBand* band, ParticleArrays& out,
              const LevelSet* escaped_from = nullptr) const;

  /// Fills the band about φ's surface afresh (the start of a run).
  void seed(const LevelSet& phi, const ShellGeometry& shells);
  void advect(const NodeFields& velocity, double dt, const ShellGeometry& shells_n,
              const geometry::ShellBand* band);
  /// `shells_n`, `shells_np1`: the shells at the start and the end of the step (the same
  /// meshes moved; otherwise the paths are only tested against the shells at n+1).
  void collide(const LevelSet& phi, const ShellGeometry& shells_n,
               const ShellGeometry& shells_np1, const geometry::ShellBand* band);
  /// Returns the number of nodes changed.
  std::int64_t correct(LevelSet& phi, const ShellGeometry& shells);
  void adjust(const LevelSet& phi, const ShellGeometry& shells);
  /// Deletes the air particles in the node box `nodes` that lie in water: an emitter that
  /// has just set φ there overrides them (they would raise φ back as escaped particles).
  void drop_air_in_water(const LevelSet& phi, const grid::IndexBox& nodes);
  /// Tops up the band cells among those of the node box `nodes` (an emitter's water).
  void top_up(const LevelSet& phi, const ShellGeometry& shells, const grid::IndexBox& nodes);
  /// Reseeds when the frame at time t (after the step) is a multiple of reseed_every.
  void reseed_if_due(double t, const LevelSet& phi, const ShellGeometry& shells);

  void save(sdk::StateWriter& out) const;
  void restore(sdk::StateReader& in);

 private:
  std::optional<double> phi_at(const LevelSet& phi, const Eigen::Vector3d& p,
                               const ShellGeometry& shells) const;
  Eigen::Vector3d velocity_at(const NodeFields& velocity, const Eigen::Vector3d& p,
                              const ShellGeometry& shells, bool rays) const;
  /// Stops the path from the start position to particle i's position at the shells;
  /// returns false when the particle must be deleted.
  bool stop_at_shells(std::int64_t i, const ShellGeometry& shells);
  /// The same against shells moving from n to n+1 (`swept`: one hierarchy per shell).
  bool stop_at_moving_shells(std::int64_t i, const ShellGeometry& shells_n,
                             const ShellGeometry& shells_np1,
                             const std::vector<geometry::SweptTriangleBvh>& swept);
  /// Where a water particle at p nearer the shells than `collision` moves to: out along the
  /// distance gradient to that distance (§4.4.2); none when it is far enough or the move
  /// would cross a shell. `side`: a point on p's side (see ShellGeometry::nearest).
  std::optional<Eigen::Vector3d> off_shells(const Eigen::Vector3d& p, const Eigen::Vector3d& side,
                                            double collision, const ShellGeometry& shells) const;
  /// Seeds the band cells holding fewer than per_cell (all cells, or those of `within`);
  /// `top_up`: first trims cells holding more than twice per_cell.
  void seed_cells(const LevelSet& phi, const ShellGeometry& shells, bool top_up,
                  const grid::IndexBox* within);
  /// Moves the spray drops ballistically over dt; deletes those whose path meets a shell
  /// or leaves the domain.
  void advance_spray(double dt, const ShellGeometry& shells);
  /// Moves `to`, the end of a water particle's path from `from`, back to its collision
  /// distance off each wall, or to no nearer than `from` was, but at least 0.1Δx off.
  void keep_off_walls(const Eigen::Vector3d& from, Eigen::Vector3d& to, double collision) const;
  /// Keeps the particles with keep[i] != 0, in order (and their start positions and path
  /// velocities while those are kept in step).
  void compact(const std::vector<std::uint8_t>& keep);
  std::int64_t cell_of(std::int64_t i) const;
  /// Whether the cell holding x has its lowest corner flagged in `node_flags` (a shell
  /// band's node flags): only there can a particle's path or stencil meet a shell.
  bool in_cell_band(std::span<const std::uint8_t> node_flags, const Eigen::Vector3d& x) const;

  grid::UniformGrid m_grid;    ///< φ's lattice: velocities, corrections
  grid::UniformGrid m_domain;  ///< the MAC grid: seeding cells, walls, the box
  LevelSetAdvector m_sampler;
  int m_per_cell = 0;
  int m_reseed_every = 10;  ///< frames
  double m_fps = 24.0;
  std::uint64_t m_seed = 0;
  std::int64_t m_round = 0;       ///< seeding rounds so far (part of each particle's seed)
  std::int64_t m_last_frame = 0;  ///< the frame of the last reseed
  double m_band = 0.0;            ///< seeding band half-width [m]: 3Δx
  double m_r_min = 0.0, m_r_max = 0.0;
  std::vector<double> m_x, m_y, m_z, m_radius, m_collision;
  std::vector<std::int8_t> m_sign;
  std::vector<double> m_x0, m_y0, m_z0;  ///< positions at the start of the step
  std::vector<double> m_u, m_v, m_w;     ///< velocity of the last path (the spray's start)
  Eigen::Vector3d m_gravity = Eigen::Vector3d::Zero();
  std::array<bool, 6> m_walls{};
  ParticleArrays m_spray;
  std::vector<double> m_plus, m_minus;   ///< correction scratch, per node (touched only)
  std::vector<std::uint8_t> m_touched;
  ParticleStats m_stats;
};

}  // namespace shellflow::grid_fluid
