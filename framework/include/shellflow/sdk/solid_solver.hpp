#pragma once
// SolidSolver: a solid is a black box to the coupling loop (§5). It exposes its thin
// shells, advances under per-triangle fluid forces with its own substeps, and can save
// and restore its full state so the runtime can look ahead and rewind (§4.3, §6).

#include <limits>
#include <span>

#include "shellflow/sdk/metrics.hpp"
#include "shellflow/sdk/shell_surface.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::sdk {

class SolidSolver {
 public:
  virtual ~SolidSolver() = default;

  /// The surfaces the fluid sees, in the current state. Their number, order and
  /// triangles never change during a run; positions and velocities follow advance().
  virtual std::span<const ShellSurface> surfaces() const = 0;

  /// Largest step advance() may be asked to take; +inf when the solver substeps itself.
  virtual double stable_dt() const { return std::numeric_limits<double>::infinity(); }

  /// Surfaces of the other solids of the scene at the start of the next advance(), with
  /// their node velocities, for collisions (a cloth draped over a kinematic cup). Called
  /// before every advance(); a solver may extrapolate them linearly over the step.
  virtual void set_colliders(ShellSet /*colliders*/) {}

  /// Advance from time t to t + dt. `triangle_forces[s]` holds one force [N] per
  /// triangle of surface s (§5.1: pressure jump × area along the normal); an empty
  /// span or an empty matrix means no fluid force. A rigid solver sums them into a
  /// force and a torque, a cloth gives a third of each to the triangle's nodes.
  virtual void advance(double t, double dt, std::span<const TriangleVectors> triangle_forces) = 0;

  /// Full state, bit for bit: restore(save()) followed by advance() must reproduce the
  /// same numbers as advance() alone.
  virtual void save(StateWriter& out) const = 0;
  virtual void restore(StateReader& in) = 0;

  /// Per-step figures for metrics.csv (energy, iterations, contacts, ...).
  virtual void report(Metrics& /*out*/) const {}
};

}  // namespace shellflow::sdk
