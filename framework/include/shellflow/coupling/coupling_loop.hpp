#pragma once
// The coupling loop of §6 (Guendelman et al. 2005), owned by the runtime, not by a
// plugin. With a fluid, the solids run one step ahead of it:
//
//   solids at x^{n+1}, fluid at u^n, shells at time n kept from the last step
//   1. u*      = fluid.advect(dt_n; shells^n, shells^{n+1})              §4.1–4.2
//   2. F       = fluid.coupling_forces(dt_n; shells^{n+1})               §5.1 eq. (5)–(6)
//   3. solids advance n+1 -> n+2 under F with dt_{n+1} (own substeps)    §5
//   4. v_eff   = (x^{n+2} − x^{n+1}) / dt_{n+1}                          §4.3
//   5. u^{n+1} = fluid.project(dt_n; shells^{n+1}, v_eff)                §4.3 eq. (3)–(4)
//
// F of step 2 is the impulse of the fluid over dt_n; the solids get F dt_n / dt_{n+1}
// over their step, so the momentum handed over does not depend on the step sizes.
// dt_{n+1} is chosen when the solids take step 3; if the fluid later needs a smaller
// step (its CFL after projection, a frame boundary), the solids are restored to
// x^{n+1} and re-advanced with the smaller step under the same impulse, so the
// look-ahead always matches the step the fluid takes. Without a fluid the solids simply
// advance; without solids the fluid runs steps 1 and 5 with no shells.

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/sdk/solid_solver.hpp"

namespace shellflow::coupling {

/// Wall-clock seconds spent in each phase of one step.
struct PhaseTimes {
  double advect = 0.0;
  double coupling_forces = 0.0;
  double solids = 0.0;
  double project = 0.0;
};

struct StepLimits {
  double cfl = 0.9;
  std::optional<double> max_dt;
};

class CouplingLoop {
 public:
  /// `fluid` may be null; the solvers are borrowed and must outlive the loop.
  CouplingLoop(sdk::FluidSolver* fluid, std::vector<sdk::SolidSolver*> solids, StepLimits limits);

  /// Starts at time t0 (with a fluid: advances the solids one step ahead, unforced).
  void start(double t0, double time_to_first_frame);

  /// The step the loop will take next; never past `time_to_frame_end` (> 0).
  double next_dt(double time_to_frame_end) const;

  /// One step from time() to time() + dt, dt from next_dt().
  PhaseTimes step(double dt, double time_to_frame_end_after_step);

  double time() const { return m_time; }
  /// Shells at time(): what writers see and what the fluid has been projected against.
  sdk::ShellSet shells() const { return m_shells_n; }
  /// Names of the solids' surfaces must be unique; returns the first duplicate, if any.
  std::optional<std::string> duplicate_surface_name() const;

  /// The whole state of a started loop, for a checkpoint: the loop's own (time, shells at
  /// n, the solids' saved states at n+1, the last forces and their step, the look-ahead
  /// step), then the fluid's and each solid's save(). restore() replaces start() on
  /// resume: the next step() is then bit for bit the step the saved loop would have taken.
  void save(sdk::StateWriter& out) const;
  /// @throw Error when the state was saved by a loop with other solvers or shells.
  void restore(sdk::StateReader& in);

 private:
  std::vector<sdk::ShellSurface> gather_shells() const;
  void advance_solids(double t, double dt, std::span<const sdk::TriangleVectors> forces);
  double solids_stable_dt() const;
  void save_solids();
  /// m_forces scaled by m_forces_dt / dt_solid (the same impulse over the solids' step).
  std::vector<sdk::TriangleVectors> impulse_matched_forces(double dt_solid) const;
  double limit_dt(double dt, double time_to_frame_end) const;

  sdk::FluidSolver* m_fluid;
  std::vector<sdk::SolidSolver*> m_solids;
  StepLimits m_limits;
  double m_time = 0.0;
  std::vector<sdk::ShellSurface> m_shells_n;  ///< at m_time
  // With a fluid only: the solids are at m_time + m_ahead_dt.
  double m_ahead_dt = 0.0;
  std::vector<sdk::StateBuffer> m_solid_states_np1;  ///< solids at n+1, for a re-advance
  std::vector<sdk::TriangleVectors> m_forces;        ///< forces per surface, last step
  double m_forces_dt = 0.0;                          ///< the fluid step they were computed for
};

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace shellflow::coupling
