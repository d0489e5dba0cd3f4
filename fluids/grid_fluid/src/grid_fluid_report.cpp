// GridFluid's metrics (report()), the drift warnings of its water, and plan(): what a
// step of the scene computes.
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "shellflow/grid_fluid/mac/ordered_sum.hpp"
#include "shellflow/grid_fluid/water/water_energy.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

double GridFluid::smoke_mass() const {
  const auto& rho = m_nodes.density();
  const double sum =
      ordered_sum(static_cast<std::int64_t>(rho.size()), [&](std::int64_t i) { return rho[i]; });
  const double dx = m_mac.dx();
  return sum * dx * dx * dx;
}

void GridFluid::report_water(sdk::Metrics& out) const {
  const auto& p = m_stats.projection;
  const auto& w = m_liquid->stats();
  // Against the shells where the water is now (m_geometry_np1 holds the step's start).
  const double volume = m_liquid->volume(m_geometry_n.get(), m_band_used ? &m_band : nullptr);
  out.set("water_volume", volume);
  out.set("water_volume_change", volume - m_liquid->initial_volume());
  const VolumeBudget& budget = m_liquid->budget();
  out.set("water_volume_added", budget.added);
  out.set("water_volume_outflow", budget.outflow);
  const double held = m_liquid->initial_volume() + budget.added - budget.outflow;
  out.set("water_volume_drift", volume - held);
  warn_of_volume_drift(volume, held);
  if (const PhaseDrift* d = m_liquid->phase_drift()) {
    out.set("water_drift_advection", d->advection);
    out.set("water_drift_shells", d->shells);
    out.set("water_drift_reinitialization", d->reinitialization);
    out.set("water_drift_between_steps", d->between_steps);
  }
  if (m_prescribed)
    out.set("water_symmetric_difference",
            m_liquid->level_set().symmetric_difference(m_initial_phi));
  // The energy of the water the last projection saw (none before it, nor in a
  // prescribed flow): K + P is what shellflow bench's energy_change follows.
  const FreeSurface& surface = m_liquid->last_surface();
  if (surface.cell_phi.size() == static_cast<size_t>(m_mac.grid().size(Location::Cell))) {
    const WaterEnergy e = water_energy(m_mac, surface, m_density, m_context.gravity,
                                       m_liquid->fraction().values());
    out.set("kinetic_energy", e.kinetic);
    out.set("potential_energy", e.potential);
    out.set("max_liquid_speed", e.max_liquid_speed);
    out.set("max_surface_face_speed", e.max_surface_face_speed);
  }
  if (m_liquid->fraction().enabled()) {
    // What F keeps that φ does not show (layers thinner than half a cell on a wall), and
    // what keeping F in [0, 1] cost.
    const VolumeFractionStats& f = m_liquid->fraction().stats();
    out.set("water_volume_level_set", m_liquid->level_set().volume());
    out.set("water_fraction_clipped", m_liquid->fraction().clipped_total());
    out.set("water_fraction_divergence", f.divergence);
    out.set("water_fraction_parts", static_cast<double>(f.parts));
    out.set("water_fraction_excess", f.excess);
    out.set("water_fraction_mixed_cells", static_cast<double>(f.mixed_cells));
  }
  out.set("liquid_cells", static_cast<double>(p.liquid_cells));
  out.set("pressure_solve_cells", static_cast<double>(p.solve_cells));
  out.set("level_set_invalid_cells", static_cast<double>(w.invalid_cells));
  out.set("fmm_interface_cells", static_cast<double>(w.reinitialization.interface_nodes));
  out.set("fmm_marched_cells", static_cast<double>(w.reinitialization.marched_nodes));
  out.set("extrapolated_faces", static_cast<double>(w.extrapolation.extrapolated_faces));
  out.set("extrapolation_invalid_faces", static_cast<double>(w.extrapolation.invalid_faces));
  out.set("t_level_set", w.t_level_set);
  out.set("t_reinitialize", w.t_reinitialize);
  out.set("t_extrapolate", w.t_extrapolate);
  if (m_liquid->particles().enabled()) {
    const ParticleStats& q = w.particles;
    out.set("particles_negative", static_cast<double>(q.negative));
    out.set("particles_positive", static_cast<double>(q.positive));
    out.set("particles_escaped", static_cast<double>(q.escaped));
    out.set("particles_corrected_cells", static_cast<double>(q.corrected_nodes));
    out.set("particles_deleted_at_shells", static_cast<double>(q.deleted_at_shells));
    out.set("particles_kept_off_shells", static_cast<double>(q.kept_off_shells));
    out.set("particles_removed", static_cast<double>(q.removed));
    out.set("particles_reseeded", static_cast<double>(q.reseeded));
    out.set("particles_spray", static_cast<double>(q.spray));
    out.set("t_particles", q.seconds);
  }
}

void GridFluid::report(sdk::Metrics& out) const {
  const auto& p = m_stats.projection;
  out.set("pcg_iterations", p.iterations);
  out.set("pcg_max_region_iterations", p.max_region_iterations);
  out.set("pcg_relative_residual", p.relative_residual);
  out.set("pressure_converged", p.converged ? 1.0 : 0.0);
  out.set("max_divergence", p.max_relative_divergence);
  out.set("fluid_regions", p.regions);
  out.set("enclosed_regions", p.enclosed_regions);
  out.set("compatibility_flux", p.max_compatibility_flux);
  out.set("shell_neumann_faces", static_cast<double>(p.shell_neumann_faces));
  out.set("band_nodes", static_cast<double>(m_stats.band_nodes));
  out.set("invalid_nodes", static_cast<double>(m_stats.refill.invalid_nodes));
  out.set("refill_from_object",
          static_cast<double>(m_stats.refill.refill.from_object + m_stats.refill.refill.isolated));
  // What each phase's storage holds, written in both modes (cost follows need reads them):
  // smoke keeps no level set, water no smoke density and temperature.
  out.set("level_set_cells",
          m_liquid ? static_cast<double>(m_liquid->level_set().phi().size()) : 0.0);
  out.set("smoke_nodes", static_cast<double>(m_nodes.density().size()));
  if (m_liquid) {
    report_water(out);
  } else {
    out.set("smoke_mass", smoke_mass());
    // ½ ρ Σ u² Δx³ over the MAC faces: with the solids' energies, what a stability sweep
    // (shellflow bench's energy_ratio) watches. Smoke only: a water scene's air faces hold
    // extrapolated velocities that carry no energy.
    double sum = 0.0;
    for (int a = 0; a < 3; ++a) {
      const auto& u = m_mac.face_velocity(a);
      sum += ordered_sum(static_cast<std::int64_t>(u.size()),
                         [&](std::int64_t f) { return u[f] * u[f]; });
    }
    const double dx = m_mac.dx();
    out.set("kinetic_energy", 0.5 * m_density * sum * dx * dx * dx);
  }
  out.set("t_pressure", m_t_pressure);
  out.set("max_speed", max_flow_speed());
  const auto& c = m_stats.coupling;
  out.set("coupling_faces", static_cast<double>(c.coupled_faces));
  out.set("coupling_rigid_faces", static_cast<double>(c.rigid_faces));
  out.set("coupling_iterations", c.iterations);
  out.set("coupling_relative_residual", c.relative_residual);
  out.set("coupling_max_pressure_jump", c.max_pressure_jump);
  out.set("coupling_force_x", c.total_force.x());
  out.set("coupling_force_y", c.total_force.y());
  out.set("coupling_force_z", c.total_force.z());
  out.set("coupling_triangles_without_jump", static_cast<double>(c.triangles_without_jump));
  m_probes.report(out, m_mac, m_nodes.density(), m_liquid ? &m_liquid->level_set() : nullptr,
                  m_liquid ? &m_liquid->fraction() : nullptr);
}

void GridFluid::warn_of_volume_drift(double volume, double held) const {
  // A scene loses or makes water silently otherwise: metrics.csv has the figures, but the
  // run's log is what a user watches. Levels of |drift| against what the scene holds.
  static constexpr std::array<double, 4> kDriftWarnings = {0.05, 0.25, 0.5, 0.9};
  if (m_drift_warnings >= static_cast<int>(kDriftWarnings.size()) || !(held > 0.0)) return;
  const double drift = (volume - held) / held;
  int level = m_drift_warnings;
  while (level < static_cast<int>(kDriftWarnings.size()) &&
         std::abs(drift) >= kDriftWarnings[level])
    ++level;
  if (level == m_drift_warnings) return;
  const bool first = m_drift_warnings == 0;
  m_drift_warnings = level;
  std::string where;
  if (const PhaseDrift* d = m_liquid->phase_drift()) {
    const std::array<std::pair<double, const char*>, 3> phases = {
        {{d->advection, "the advection"},
         {d->shells, "the shells' move"},
         {d->reinitialization, "the particles' correction and reinitialisation"}}};
    const auto most = std::max_element(
        phases.begin(), phases.end(),
        [](const auto& a, const auto& b) { return std::abs(a.first) < std::abs(b.first); });
    where = fmt::format("; {:+.3g} m^3 of it in {}", most->first, most->second);
  }
  // Why and what to do, the first time only.
  const char* why =
      !first ? ""
             : " Water thinner than a cell against a shell is lost, and with the level set "
               "alone (/fluid/water/volume_fraction false) thin and curved water too: "
               "docs/known-limits.md says what keeps more; \"volume_by_phase\": true in "
               "/fluid/water says which phase drifts.";
  spdlog::warn(
      "grid_fluid: the water's volume is {:+.1f} % off what the scene holds at t = {:.4g} s "
      "({:.4g} m^3 against {:.4g} m^3 from the start, the emitters and the open sides{}).{}",
      100.0 * drift, m_time, volume, held, where, why);
}

std::vector<sdk::PlanEntry> GridFluid::plan() const {
  std::vector<sdk::PlanEntry> out;
  if (m_liquid) {
    out.push_back({"water", true,
                   "/fluid/water given: level set on the cell centres, fast marching, velocity "
                   "extrapolation, free-surface pressure (§4.4)"});
    out.push_back({"volume_fraction", m_liquid->fraction().enabled(),
                   m_liquid->fraction().enabled()
                       ? "/fluid/water/volume_fraction: each cell's water carried beside φ "
                         "(Weymouth and Yue 2010) and φ moved to it"
                       : "no /fluid/water/volume_fraction: the water's volume is φ's"});
    out.push_back({"maccormack_level_set", m_liquid->maccormack(),
                   m_liquid->maccormack()
                       ? "/fluid/water/advection = maccormack: φ traced forward and back, "
                         "corrected (Selle et al. 2008)"
                       : "/fluid/water/advection = semi_lagrangian: the paper's trilinear "
                         "step for φ (§4.4.1)"});
    out.push_back({"particle_level_set", m_liquid->particles().enabled(),
                   m_liquid->particles().enabled()
                       ? "/fluid/water/particles/per_cell > 0: marker particles correct the "
                         "level set (§4.4.2)"
                       : "/fluid/water/particles/per_cell = 0: the level set alone"});
    out.push_back({"prescribed_velocity", m_prescribed.has_value(),
                   m_prescribed ? "/fluid/prescribed_velocity given: the water is carried by "
                                  "an analytic field; no gravity, pressure solve or velocity "
                                  "extrapolation"
                                : "no /fluid/prescribed_velocity: the velocity is solved for"});
    out.push_back({"smoke", false,
                   "a water scene: no density, temperature, buoyancy or "
                   "vorticity confinement"});
  } else {
    out.push_back({"water", false, "no /fluid/water: no level set"});
    out.push_back({"smoke", true,
                   std::string("smoke density") + (m_temperature ? ", temperature" : "") +
                       (m_vorticity > 0.0 ? ", vorticity confinement" : "")});
  }
  return out;
}

}  // namespace shellflow::grid_fluid
