#include "shellflow/coupling/coupling_loop.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "shellflow/sdk/error.hpp"

namespace shellflow::coupling {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

/// The fluid solves over Δt_n and a rigid body's V* is v + a Δt_n, but the solid then adds
/// a over the look-ahead step Δt_{n+1}. Scaling a by Δt_{n+1}/Δt_n makes the solve balance
/// exactly the velocity the solid will gain: without it a floating body got a kick
/// m a (Δt_{n+1} - Δt_n) at each frame end, where the steps are cut to land on it.
/// Empty when no shell is rigid (nothing to copy).
std::vector<sdk::ShellSurface> with_rigid_accelerations_over_solid_step(
    const std::vector<sdk::ShellSurface>& shells, double solid_steps_per_fluid_step) {
  if (std::none_of(shells.begin(), shells.end(), [](const auto& s) { return s.rigid; }))
    return {};
  std::vector<sdk::ShellSurface> scaled(shells);
  for (auto& s : scaled)
    if (s.rigid) s.rigid->acceleration *= solid_steps_per_fluid_step;
  return scaled;
}

/// §6's effective velocity of each shell over a step: (x_to − x_from)/Δt per node (empty
/// for a shell whose node count changed).
std::vector<sdk::Positions> effective_velocities(const std::vector<sdk::ShellSurface>& from,
                                                 const std::vector<sdk::ShellSurface>& to,
                                                 double dt) {
  std::vector<sdk::Positions> v(to.size());
  for (size_t s = 0; s < to.size() && s < from.size(); ++s)
    if (to[s].positions.rows() == from[s].positions.rows())
      v[s] = (to[s].positions - from[s].positions) / dt;
  return v;
}
}  // namespace

CouplingLoop::CouplingLoop(sdk::FluidSolver* fluid, std::vector<sdk::SolidSolver*> solids,
                           StepLimits limits)
    : m_fluid(fluid), m_solids(std::move(solids)), m_limits(limits) {}

std::vector<sdk::ShellSurface> CouplingLoop::gather_shells() const {
  std::vector<sdk::ShellSurface> all;
  for (const auto* solid : m_solids)
    for (const auto& s : solid->surfaces()) all.push_back(s);
  return all;
}

std::optional<std::string> CouplingLoop::duplicate_surface_name() const {
  std::set<std::string> seen;
  for (const auto* solid : m_solids)
    for (const auto& s : solid->surfaces())
      if (!seen.insert(s.name).second) return s.name;
  return std::nullopt;
}

double CouplingLoop::solids_stable_dt() const {
  double dt = kInf;
  for (const auto* solid : m_solids) dt = std::min(dt, solid->stable_dt());
  return dt;
}

double CouplingLoop::limit_dt(double dt, double time_to_frame_end) const {
  if (m_limits.max_dt) dt = std::min(dt, *m_limits.max_dt);
  // Land exactly on the frame end; split the rest evenly rather than leave a sliver. Time
  // left that exceeds the step by round-off only (t accumulates it: 50 fps with max_dt
  // 0.02 s left 0.0200000000002) is taken whole rather than halved.
  constexpr double kRoundOff = 1e-9;
  if (dt >= time_to_frame_end * (1.0 - kRoundOff)) return time_to_frame_end;
  if (dt > 0.5 * time_to_frame_end) return 0.5 * time_to_frame_end;
  return dt;
}

double CouplingLoop::next_dt(double time_to_frame_end) const {
  double dt = solids_stable_dt();
  if (m_fluid) dt = std::min(dt, m_fluid->stable_dt(m_limits.cfl));
  return limit_dt(dt, time_to_frame_end);
}

void CouplingLoop::advance_solids(double t, double dt,
                                  std::span<const sdk::TriangleVectors> forces) {
  // Each solid sees the others at the start of the step (cloth on a kinematic cup).
  const auto all = gather_shells();
  size_t offset = 0;
  for (auto* solid : m_solids) {
    const size_t count = solid->surfaces().size();
    std::vector<sdk::ShellSurface> others;
    others.reserve(all.size() - count);
    for (size_t i = 0; i < all.size(); ++i)
      if (i < offset || i >= offset + count) others.push_back(all[i]);
    solid->set_colliders(others);
    const auto own =
        forces.empty() ? std::span<const sdk::TriangleVectors>() : forces.subspan(offset, count);
    solid->advance(t, dt, own);
    offset += count;
  }
}

std::vector<sdk::TriangleVectors> CouplingLoop::impulse_matched_forces(double dt_solid) const {
  // The coupling pressure of step n is the impulse the fluid gives over Δt_n (§5.1 eq. (5));
  // handing F Δt_n / Δt_solid to a solid that steps Δt_solid passes on exactly that
  // impulse, so momentum is exchanged without loss when the step size changes.
  std::vector<sdk::TriangleVectors> scaled(m_forces);
  if (m_forces_dt > 0.0 && dt_solid > 0.0)
    for (auto& f : scaled) f *= m_forces_dt / dt_solid;
  return scaled;
}

void CouplingLoop::start(double t0, double time_to_first_frame) {
  m_time = t0;
  m_shells_n = gather_shells();
  m_forces.assign(m_shells_n.size(), sdk::TriangleVectors());
  if (!m_fluid || m_solids.empty()) return;
  // Put the solids one step ahead of the fluid, unforced (no pressure yet), keeping
  // their state at t0 in case the fluid's first step differs.
  m_ahead_dt = next_dt(time_to_first_frame);
  save_solids();
  advance_solids(m_time, m_ahead_dt, {});
  // The fluid at t0 learns how the shells move over the first step (its pressure impulse).
  m_fluid->start(m_ahead_dt, m_shells_n,
                 effective_velocities(m_shells_n, gather_shells(), m_ahead_dt));
}

void CouplingLoop::save_solids() {
  m_solid_states_np1.resize(m_solids.size());
  for (size_t i = 0; i < m_solids.size(); ++i) {
    m_solid_states_np1[i].clear();
    sdk::StateWriter out(m_solid_states_np1[i]);
    m_solids[i]->save(out);
  }
}

PhaseTimes CouplingLoop::step(double dt, double time_to_frame_end_after_step) {
  PhaseTimes times;
  if (!m_fluid) {
    const auto t0 = Clock::now();
    advance_solids(m_time, dt, {});
    times.solids = seconds_since(t0);
    m_time += dt;
    m_shells_n = gather_shells();
    return times;
  }

  if (!m_solids.empty() && std::abs(dt - m_ahead_dt) > 1e-12 * std::max(dt, m_ahead_dt)) {
    // The solids looked ahead with a step the fluid does not take: rewind them to n+1
    // and advance again, under the same forces, with the step actually taken.
    for (size_t i = 0; i < m_solids.size(); ++i) {
      sdk::StateReader in(m_solid_states_np1[i]);
      m_solids[i]->restore(in);
    }
    const auto t0 = Clock::now();
    advance_solids(m_time, dt, impulse_matched_forces(dt));
    times.solids += seconds_since(t0);
    m_ahead_dt = dt;
  }
  const auto shells_np1 = gather_shells();

  auto t0 = Clock::now();
  m_fluid->advect(m_time, dt, m_shells_n, shells_np1);
  times.advect = seconds_since(t0);

  std::vector<sdk::Positions> effective_velocity(shells_np1.size());
  if (!m_solids.empty()) {
    // The look-ahead step n+1 -> n+2 the solids will take under these forces; neither the
    // coupling solve nor anything before it changes what it depends on.
    const double dt_next =
        limit_dt(std::min(solids_stable_dt(), m_fluid->stable_dt(m_limits.cfl)),
                 time_to_frame_end_after_step > 0 ? time_to_frame_end_after_step : kInf);
    t0 = Clock::now();
    m_forces.resize(shells_np1.size());
    for (size_t s = 0; s < shells_np1.size(); ++s)
      m_forces[s] = sdk::TriangleVectors::Zero(shells_np1[s].triangle_count(), 3);
    const auto rescaled = with_rigid_accelerations_over_solid_step(shells_np1, dt_next / dt);
    m_fluid->coupling_forces(dt, rescaled.empty() ? shells_np1 : rescaled, m_forces);
    m_forces_dt = dt;
    times.coupling_forces = seconds_since(t0);

    // Look ahead: solids n+1 -> n+2 under the coupling forces (§6).
    t0 = Clock::now();
    save_solids();
    advance_solids(m_time + dt, dt_next, impulse_matched_forces(dt_next));
    m_ahead_dt = dt_next;
    effective_velocity = effective_velocities(shells_np1, gather_shells(), dt_next);
    times.solids += seconds_since(t0);
  }

  t0 = Clock::now();
  m_fluid->project(dt, shells_np1, effective_velocity);
  times.project = seconds_since(t0);

  m_time += dt;
  m_shells_n = shells_np1;
  return times;
}

namespace {
constexpr std::uint32_t kLoopStateTag = 0x53464c31;  // "SFL1"
}

void CouplingLoop::save(sdk::StateWriter& out) const {
  out.write(kLoopStateTag);
  out.write(m_time);
  out.write(m_ahead_dt);
  out.write(m_forces_dt);
  out.write<std::uint64_t>(m_shells_n.size());
  for (const auto& s : m_shells_n) {
    out.write_matrix(s.positions);
    out.write_matrix(s.velocities);
    out.write_matrix(s.surface_density);
  }
  out.write<std::uint64_t>(m_solid_states_np1.size());
  for (const auto& state : m_solid_states_np1) out.write_bytes(state);
  out.write<std::uint64_t>(m_forces.size());
  for (const auto& f : m_forces) out.write_matrix(f);
  // The solvers' own states, each in its own length-prefixed block so that a solver
  // reading less or more than it wrote is caught here, not by the next solver.
  out.write<std::uint8_t>(m_fluid != nullptr);
  if (m_fluid) out.write_block([&](sdk::StateWriter& w) { m_fluid->save(w); });
  out.write<std::uint64_t>(m_solids.size());
  for (const auto* solid : m_solids) out.write_block([&](sdk::StateWriter& w) { solid->save(w); });
}

void CouplingLoop::restore(sdk::StateReader& in) {
  const auto mismatch = [](const std::string& what) {
    return Error("the saved coupling loop state does not fit this scene: " + what);
  };
  if (in.read<std::uint32_t>() != kLoopStateTag) throw mismatch("not a coupling loop state");
  const double time = in.read<double>();
  const double ahead_dt = in.read<double>();
  const double forces_dt = in.read<double>();
  // Solvers first (the shells' topology, names and flags come from them), then the
  // loop's copies of the shells at n over what the solids expose at n+1.
  const auto shell_count = in.read<std::uint64_t>();
  std::vector<sdk::Positions> positions(shell_count), velocities(shell_count);
  std::vector<Eigen::VectorXd> densities(shell_count);
  for (std::uint64_t s = 0; s < shell_count; ++s) {
    in.read_matrix(positions[s]);
    in.read_matrix(velocities[s]);
    in.read_matrix(densities[s]);
  }
  std::vector<sdk::StateBuffer> states_np1(in.read<std::uint64_t>());
  for (auto& state : states_np1) state = in.read_bytes();
  std::vector<sdk::TriangleVectors> forces(in.read<std::uint64_t>());
  for (auto& f : forces) in.read_matrix(f);
  const bool has_fluid = in.read<std::uint8_t>() != 0;
  if (has_fluid != (m_fluid != nullptr))
    throw mismatch(has_fluid ? "it has a fluid, the scene has none" : "it has no fluid");
  if (m_fluid) {
    const auto fluid = in.read_bytes();
    sdk::StateReader r(fluid);
    m_fluid->restore(r);
    if (!r.at_end()) throw mismatch("the fluid's state is longer than the fluid reads");
  }
  const auto solid_count = in.read<std::uint64_t>();
  if (solid_count != m_solids.size())
    throw mismatch(std::to_string(solid_count) + " solids saved, the scene has " +
                   std::to_string(m_solids.size()));
  for (size_t i = 0; i < m_solids.size(); ++i) {
    const auto state = in.read_bytes();
    sdk::StateReader r(state);
    m_solids[i]->restore(r);
    if (!r.at_end())
      throw mismatch("solid " + std::to_string(i) + "'s state is longer than it reads");
  }
  auto shells = gather_shells();
  if (shells.size() != shell_count)
    throw mismatch(std::to_string(shell_count) + " shells saved, the scene has " +
                   std::to_string(shells.size()));
  for (size_t s = 0; s < shells.size(); ++s) {
    if (positions[s].rows() != shells[s].node_count())
      throw mismatch("shell '" + shells[s].name + "' has another node count");
    shells[s].positions = std::move(positions[s]);
    shells[s].velocities = std::move(velocities[s]);
    shells[s].surface_density = std::move(densities[s]);
  }
  if (!in.at_end()) throw mismatch("it is longer than the loop reads");
  m_time = time;
  m_ahead_dt = ahead_dt;
  m_forces_dt = forces_dt;
  m_shells_n = std::move(shells);
  m_solid_states_np1 = std::move(states_np1);
  m_forces = std::move(forces);
}

}  // namespace shellflow::coupling
