// GridFluid::save() and restore(): the fluid's state in a checkpoint.
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"

#include <algorithm>

#include "shellflow/grid_fluid/water/level_set_state.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

void GridFluid::save(sdk::StateWriter& out) const {
  if (m_cut_water)
    throw Error(
        "/fluid/water/cut_cells: the parts' water and velocities are not saved in checkpoints "
        "yet (docs/cut-cells.md, C5); run with --checkpoint-every 0, or set "
        "/fluid/water/cut_cells to false");
  // Any contiguous array of doubles (std::vector, Eigen::VectorXd), as a column.
  const auto write_vector = [&](const auto& v) {
    out.write_column(v.data(), static_cast<std::int64_t>(v.size()));
  };
  out.write(m_time);
  for (int a = 0; a < 3; ++a) write_vector(m_mac.face_velocity(a));
  write_vector(m_mac.pressure());
  write_vector(m_nodes.density());
  write_vector(m_nodes.temperature());
  for (int a = 0; a < 3; ++a) write_vector(m_nodes.velocity(a));
  write_vector(m_projection.scaled_pressure());
  out.write(m_coupling != nullptr);
  if (m_coupling) write_vector(m_coupling->scaled_pressure());
  if (m_liquid) {
    save_level_set(out, m_liquid->level_set());
    m_liquid->particles().save(out);
  }
  // What stable_dt() reads besides the fields: the shells' speed of the last projection
  // and the body force of the last step. Without them a restored fluid (a resumed run)
  // would choose another step than the run it continues.
  out.write(m_shell_speed);
  out.write(m_stats.max_force);
  if (m_liquid) {
    out.write(m_liquid->initial_volume());
    out.write(m_liquid->budget().added);
    out.write(m_liquid->budget().outflow);
    if (const PhaseDrift* d = m_liquid->phase_drift()) {
      for (const double v : {d->advection, d->shells, d->reinitialization, d->between_steps})
        out.write(v);
      out.write(m_liquid->phase_end());
    }
    if (m_liquid->fraction().enabled()) m_liquid->fraction().save(out, m_mac);
  }
}

void GridFluid::restore(sdk::StateReader& in) {
  // Into any contiguous array of doubles, which keeps its size.
  const auto read_vector = [&](auto& v) {
    Eigen::VectorXd m;
    in.read_matrix(m);
    if (static_cast<size_t>(m.size()) != static_cast<size_t>(v.size()))
      throw Error("grid_fluid restore(): the saved state is for another grid size");
    std::copy(m.data(), m.data() + m.size(), v.data());
  };
  m_time = in.read<double>();
  for (int a = 0; a < 3; ++a) read_vector(m_mac.face_velocity(a));
  read_vector(m_mac.pressure());
  read_vector(m_nodes.density());
  read_vector(m_nodes.temperature());
  for (int a = 0; a < 3; ++a) read_vector(m_nodes.velocity(a));
  read_vector(m_projection.scaled_pressure());
  if (in.read<bool>()) read_vector(coupling_pressure().scaled_pressure());
  if (m_liquid) {
    restore_level_set(in, m_liquid->level_set());
    m_liquid->particles().restore(in);
  }
  m_shell_speed = in.read<double>();
  m_stats.max_force = in.read<double>();
  // Last, so that a state saved before it was written still restores (the scene's
  // volume then stands in, measured without the shells).
  if (m_liquid && !in.at_end()) m_liquid->set_initial_volume(in.read<double>());
  if (m_liquid && !in.at_end()) {  // likewise: saved before the budget was kept, none
    VolumeBudget budget;
    budget.added = in.read<double>();
    budget.outflow = in.read<double>();
    m_liquid->set_budget(budget);
  }
  if (m_liquid && m_liquid->phase_drift() && !in.at_end()) {
    PhaseDrift d;
    for (double* v : {&d.advection, &d.shells, &d.reinitialization, &d.between_steps})
      *v = in.read<double>();
    m_liquid->set_phase_drift(d, in.read<double>());
  }
  if (m_liquid && m_liquid->fraction().enabled()) {
    if (in.at_end())
      throw Error("grid_fluid restore(): the state holds no water fraction (it was saved without "
                  "/fluid/water/volume_fraction); run the scene afresh with --overwrite");
    m_liquid->fraction().restore(in, m_mac);
  } else if (m_liquid && !in.at_end()) {
    throw Error("grid_fluid restore(): the state holds more than this scene reads (it was saved "
                "with other /fluid/water options: volume_fraction or volume_by_phase); run the "
                "scene it was saved with, or run afresh with --overwrite");
  }
  m_geometry_n.reset();
  m_geometry_np1.reset();
  m_nodes_current = false;
}

}  // namespace shellflow::grid_fluid
