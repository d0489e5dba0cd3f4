#pragma once
// FluidSolver: a grid fluid seen by the coupling loop (§4, §5.1, §6).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "shellflow/sdk/metrics.hpp"
#include "shellflow/sdk/shell_surface.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::sdk {

/// A read-only view of one scalar or vector grid field, for writers.
struct FieldView {
  enum class Location { Node, Cell };
  std::string name;                 ///< "density", "temperature", "velocity", "phi", ...
  Location location = Location::Cell;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< world position of sample (0,0,0)
  double dx = 0.0;                  ///< sample spacing [m]
  std::array<int, 3> dims{0, 0, 0}; ///< samples per axis
  int components = 1;               ///< 1 (scalar) or 3 (vector, structure of arrays)
  /// Component c of sample (i,j,k) is data[c][i + dims[0]*(j + dims[1]*k)].
  std::array<const double*, 3> data{nullptr, nullptr, nullptr};
};

/// A read-only view of one set of particles (spray, marker particles), for writers: `count`
/// particles as flat arrays, one per coordinate (structure of arrays).
struct ParticleView {
  std::string name;        ///< "spray", "water_particles", "air_particles", ...
  std::int64_t count = 0;
  std::array<const double*, 3> position{nullptr, nullptr, nullptr};  ///< [m]
  std::array<const double*, 3> velocity{nullptr, nullptr, nullptr};  ///< [m/s]
  const double* radius = nullptr;                                    ///< [m]
};

/// The fluid's domain box and the condition on each of its six faces, for writers (a
/// preview draws the walls, so that water on the floor and water in mid-air look
/// different). Sides are numbered 2 * axis + (0 for the min face, 1 for the max face).
struct DomainView {
  enum class Side {
    Wall,    ///< closed: no flow through it
    Open,    ///< outflow: the fluid may leave through it
    Inflow,  ///< the fluid enters through it at a given velocity
  };
  Eigen::Vector3d lower = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Vector3d upper = Eigen::Vector3d::Zero();  ///< [m]
  std::array<Side, 6> sides{Side::Wall, Side::Wall, Side::Wall, Side::Wall, Side::Wall, Side::Wall};

  Side side(int axis, int max_side) const { return sides[2 * axis + max_side]; }
  bool operator==(const DomainView&) const = default;
};

/// One module of a run plan: what a scene turns on or leaves off, and why (run.json).
struct PlanEntry {
  std::string module;
  bool enabled = false;
  std::string why;
};

class FluidSolver {
 public:
  virtual ~FluidSolver() = default;

  /// Largest step allowed by the CFL number `cfl` (and any other limit of the fluid).
  virtual double stable_dt(double cfl) const = 0;

  /// §6 before the first step: the shells at t0 and their velocity over the first step
  /// (as project() gets it). A fluid at rest beside a shell already moving takes the
  /// motion's pressure impulse here; otherwise its first step leaves it behind the shell.
  /// Default: nothing.
  virtual void start(double /*dt*/, ShellSet /*shells*/,
                     std::span<const Positions> /*effective_velocity*/) {}

  /// §4.1–4.2: compute u* (advection and body forces) knowing the shells at time n and
  /// n+1; nodes swept by a shell are invalidated and refilled (§3).
  virtual void advect(double t, double dt, ShellSet shells_n, ShellSet shells_np1) = 0;

  /// §5.1 eq. (5)–(6): per-triangle forces [N] on the two-way shells from the coupling
  /// pressure solve; `triangle_forces[s]` is sized by the runtime to shells[s]'s triangles.
  virtual void coupling_forces(double dt, ShellSet shells,
                               std::span<TriangleVectors> triangle_forces) = 0;

  /// §4.3 eq. (3)–(4): make u* divergence free with Neumann faces across the shells,
  /// whose constrained velocity comes from `effective_velocity[s]` (one row per node).
  virtual void project(double dt, ShellSet shells,
                       std::span<const Positions> effective_velocity) = 0;

  virtual void save(StateWriter& out) const = 0;
  virtual void restore(StateReader& in) = 0;

  /// Fields for writers (VDB, previews); views stay valid until the next step.
  virtual std::vector<FieldView> fields() const { return {}; }

  /// Particle sets for writers (see ParticleView); views stay valid until the next step.
  virtual std::vector<ParticleView> particles() const { return {}; }

  /// Describes the first non-finite value found (field, index), or nothing.
  virtual std::optional<std::string> find_nonfinite() const { return std::nullopt; }

  virtual void report(Metrics& /*out*/) const {}

  /// The fluid's own modules for run.json's run plan (e.g. smoke or water, and why).
  virtual std::vector<PlanEntry> plan() const { return {}; }

  /// The domain box and its sides, for writers; nothing for a fluid without a box.
  virtual std::optional<DomainView> domain() const { return std::nullopt; }
};

}  // namespace shellflow::sdk
