// The §6 loop's bookkeeping: what the fluid sees at each phase, the solids' look-ahead,
// and the rewind when the fluid's step shrinks. Test doubles make every time visible.

#include "shellflow/coupling/coupling_loop.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>

namespace shellflow::coupling {
namespace {

// Positions reveal the time they belong to: x(t) = x0 + kC t^2 along x.
constexpr double kC = 3.0;
// Times recovered from positions are exact to round-off of sqrt(x / kC) at t ~ 0.1.
constexpr double kTimeTolerance = 1e-12;

double time_of(const sdk::ShellSurface& s) { return std::sqrt(s.positions(0, 0) / kC); }

/// A one-triangle solid moving on x(t) = kC t^2 regardless of forces; it records the
/// forces each advance() received.
class ClockSolid final : public sdk::SolidSolver {
 public:
  ClockSolid() {
    sdk::Triangles tris(1, 3);
    tris << 0, 1, 2;
    m_surface.name = "clock";
    m_surface.triangles = std::make_shared<const sdk::Triangles>(tris);
    m_surface.positions = sdk::Positions::Zero(3, 3);
    m_surface.velocities = sdk::Positions::Zero(3, 3);
    m_surface.surface_density = Eigen::VectorXd::Ones(1);
    m_surface.receives_fluid_forces = true;
  }
  std::span<const sdk::ShellSurface> surfaces() const override { return {&m_surface, 1}; }
  void advance(double t, double dt, std::span<const sdk::TriangleVectors> forces) override {
    EXPECT_NEAR(t, m_time, kTimeTolerance) << "advance() must start where the solid is";
    m_time = t + dt;
    m_surface.positions.col(0).setConstant(kC * m_time * m_time);
    forces_seen.push_back(forces.empty() || forces[0].rows() == 0 ? 0.0 : forces[0](0, 0));
  }
  void save(sdk::StateWriter& out) const override { out.write(m_time); out.write_matrix(m_surface.positions); }
  void restore(sdk::StateReader& in) override {
    m_time = in.read<double>();
    in.read_matrix(m_surface.positions);
  }
  std::vector<double> forces_seen;

 private:
  sdk::ShellSurface m_surface;
  double m_time = 0.0;
};

/// A fluid with a scripted stable step that records what each phase was given.
class ScriptedFluid final : public sdk::FluidSolver {
 public:
  std::deque<double> stable_steps;  ///< front() is the current answer of stable_dt()
  std::vector<std::string> calls;
  struct Seen {
    double t, dt, time_n, time_np1, effective_velocity;
  };
  std::vector<Seen> seen;

  double stable_dt(double) const override { return stable_steps.front(); }
  void start(double dt, sdk::ShellSet shells, std::span<const sdk::Positions> v) override {
    calls.push_back("start");
    started = {0.0, dt, time_of(shells[0]), 0.0, v[0](0, 0)};
  }
  Seen started{};
  void advect(double t, double dt, sdk::ShellSet n, sdk::ShellSet np1) override {
    calls.push_back("advect");
    seen.push_back({t, dt, time_of(n[0]), time_of(np1[0]), 0.0});
  }
  void coupling_forces(double, sdk::ShellSet, std::span<sdk::TriangleVectors> f) override {
    calls.push_back("coupling_forces");
    f[0].setConstant(double(seen.size()));  // step k pushes with force k
  }
  void project(double dt, sdk::ShellSet, std::span<const sdk::Positions> v) override {
    calls.push_back("project");
    seen.back().effective_velocity = v[0](0, 0);
    (void)dt;
    if (stable_steps.size() > 1) stable_steps.pop_front();  // the CFL changes after a step
  }
  void save(sdk::StateWriter&) const override {}
  void restore(sdk::StateReader&) override {}
};

TEST(CouplingLoop, FluidSeesShellsAtNAndNPlusOneAndTheLookAheadVelocity) {
  ClockSolid solid;
  ScriptedFluid fluid;
  // The step shrinks after step 2 (forcing a rewind of the look-ahead) and grows after 3.
  fluid.stable_steps = {0.01, 0.01, 0.004, 0.008};
  CouplingLoop loop(&fluid, {&solid}, {0.9, std::nullopt});
  const double frame = 1.0;
  loop.start(0.0, frame);
  for (int k = 0; k < 4; ++k) {
    const double dt = loop.next_dt(frame - loop.time());
    loop.step(dt, frame - loop.time() - dt);
  }
  ASSERT_EQ(fluid.seen.size(), 4u);
  // Before the first step the fluid learns the shells at t0 and their first step's
  // velocity, (x(0.01) − x(0)) / 0.01 (GridFluid projects with it: the water at rest
  // beside a moving shell gets its pressure impulse).
  EXPECT_EQ(fluid.calls[0], "start");
  EXPECT_NEAR(fluid.started.time_n, 0.0, kTimeTolerance);
  EXPECT_DOUBLE_EQ(fluid.started.dt, 0.01);
  EXPECT_NEAR(fluid.started.effective_velocity, kC * 0.01 * 0.01 / 0.01, 1e-12);
  EXPECT_EQ(fluid.calls[1], "advect");
  EXPECT_EQ(fluid.calls[2], "coupling_forces");
  EXPECT_EQ(fluid.calls[3], "project");
  for (size_t k = 0; k < fluid.seen.size(); ++k) {
    const auto& s = fluid.seen[k];
    EXPECT_NEAR(s.time_n, s.t, kTimeTolerance) << "step " << k;            // shells at n
    EXPECT_NEAR(s.time_np1, s.t + s.dt, kTimeTolerance) << "step " << k;   // shells at n+1
    if (k + 1 < fluid.seen.size()) {
      EXPECT_EQ(fluid.seen[k + 1].t, s.t + s.dt);  // no gaps between steps
    }
  }
  // Step 2 looked ahead with 0.01 but the fluid then took 0.004: the solid was rewound
  // and advanced again under the same force (2), so it is exactly where the fluid is.
  EXPECT_DOUBLE_EQ(fluid.seen[2].dt, 0.004);
  EXPECT_NEAR(fluid.seen[2].time_np1, fluid.seen[2].t + 0.004, kTimeTolerance);
  // Effective velocity of step 0: the look-ahead from t = 0.01 over 0.01.
  const double t1 = 0.01, t2 = 0.02;
  EXPECT_NEAR(fluid.seen[0].effective_velocity, kC * (t2 * t2 - t1 * t1) / (t2 - t1), 1e-10);
  // Forces: the unforced start, then each look-ahead under its step's force; steps 2 and
  // 3 changed dt, so their solid step was redone under the previous step's impulse: the
  // force k of a fluid step dt_k arrives as k dt_k / dt_solid (momentum kept).
  const std::vector<double> expected{0, 1, 2, 2 * 0.01 / 0.004, 3, 3 * 0.004 / 0.008, 4};
  ASSERT_EQ(solid.forces_seen.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i)
    EXPECT_DOUBLE_EQ(solid.forces_seen[i], expected[i]) << "advance " << i;
}

TEST(CouplingLoop, SolidsOnlyStepsEndExactlyOnTheFrame) {
  ClockSolid solid;
  CouplingLoop loop(nullptr, {&solid}, {0.9, 0.3});  // max_dt 0.3 over a 1 s frame
  loop.start(0.0, 1.0);
  int steps = 0;
  while (1.0 - loop.time() > 1e-12) {
    const double dt = loop.next_dt(1.0 - loop.time());
    loop.step(dt, 0.0);
    ++steps;
  }
  // 0.3, 0.3, then 0.4 remains: split as 0.2 + 0.2 rather than 0.3 + a 0.1 sliver.
  EXPECT_EQ(steps, 4);
  EXPECT_NEAR(time_of(loop.shells()[0]), 1.0, kTimeTolerance);
  for (double f : solid.forces_seen) EXPECT_EQ(f, 0.0);
}

TEST(CouplingLoop, AStepThatFitsAFrameToRoundOffLandsOnItsEnd) {
  // 50 fps with max_dt 0.02 s, stepped as the run driver does (frame ends k/50, the time
  // accumulating round-off): one step a frame. Taking the time left as more than a step
  // when it exceeded 0.02 by round-off halved the step from frame 4 on (10 frames in 14
  // steps).
  ClockSolid solid;
  CouplingLoop loop(nullptr, {&solid}, {0.9, 0.02});
  const double frame_dt = 1.0 / 50.0;
  loop.start(0.0, frame_dt);
  int steps = 0;
  for (int frame = 1; frame <= 10; ++frame) {
    const double frame_end = frame * frame_dt;
    while (frame_end - loop.time() > 1e-12 * frame_end) {
      const double remaining = frame_end - loop.time();
      const double dt = loop.next_dt(remaining);
      loop.step(dt, remaining - dt > 1e-12 * frame_end ? remaining - dt : frame_dt);
      ++steps;
    }
  }
  EXPECT_EQ(steps, 10);
  EXPECT_NEAR(loop.time(), 0.2, 1e-15);
}

}  // namespace
}  // namespace shellflow::coupling
