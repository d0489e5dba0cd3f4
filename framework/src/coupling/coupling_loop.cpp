#include "shellflow/coupling/coupling_loop.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace shellflow::coupling {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

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
  // Land exactly on the frame end; split the rest evenly rather than leave a sliver.
  if (dt >= time_to_frame_end) return time_to_frame_end;
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
    t0 = Clock::now();
    m_forces.resize(shells_np1.size());
    for (size_t s = 0; s < shells_np1.size(); ++s)
      m_forces[s] = sdk::TriangleVectors::Zero(shells_np1[s].triangle_count(), 3);
    m_fluid->coupling_forces(dt, shells_np1, m_forces);
    m_forces_dt = dt;
    times.coupling_forces = seconds_since(t0);

    // Look ahead: solids n+1 -> n+2 under the coupling forces (§6).
    t0 = Clock::now();
    const double dt_next =
        limit_dt(std::min(solids_stable_dt(), m_fluid->stable_dt(m_limits.cfl)),
                 time_to_frame_end_after_step > 0 ? time_to_frame_end_after_step : kInf);
    save_solids();
    advance_solids(m_time + dt, dt_next, impulse_matched_forces(dt_next));
    m_ahead_dt = dt_next;
    const auto shells_np2 = gather_shells();
    for (size_t s = 0; s < shells_np1.size(); ++s)
      effective_velocity[s] = (shells_np2[s].positions - shells_np1[s].positions) / dt_next;
    times.solids += seconds_since(t0);
  }

  t0 = Clock::now();
  m_fluid->project(dt, shells_np1, effective_velocity);
  times.project = seconds_since(t0);

  m_time += dt;
  m_shells_n = shells_np1;
  return times;
}

}  // namespace shellflow::coupling
