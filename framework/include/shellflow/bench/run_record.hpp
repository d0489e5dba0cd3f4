#pragma once
// One run of a bench as results.csv records it: its swept values, how it ended, what it
// cost, and its errors.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/bench/child_processes.hpp"
#include "shellflow/bench/sweep_plan.hpp"

namespace shellflow::bench {

/// How a run ended, for results.csv and the stability map.
enum class RunOutcome {
  Completed,     ///< every frame: stable
  GuardStopped,  ///< the stability guard stopped it (a speed above /coupling/max_speed)
  NonFinite,     ///< a non-finite position, velocity or fluid value stopped it
  Crashed,       ///< a signal ended the process (a segfault, an abort, the OOM killer)
  Failed,        ///< any other end: bad input, an internal error, interrupted
};
std::string to_string(RunOutcome outcome);

struct RunRecord {
  SweepPoint point;
  RunOutcome outcome = RunOutcome::Failed;
  std::string message;  ///< run.json's message, the signal, or the log's last line
  int exit_code = -1;
  double wall_seconds = 0.0;  ///< the child process, start to end [s]
  /// The run's own wall time (run.json: validation, set-up and the steps, without the
  /// process start and plugin loading); what costs are compared by [s].
  double run_seconds = 0.0;
  long long steps = 0;
  double sim_time = 0.0;  ///< simulated time reached [s]
  double peak_mb = 0.0;
  /// (E_end − E_first) / max over steps of K, with K the sum of the *.kinetic_energy
  /// columns (the solids', the fluid's) and E = K + the *.potential_energy columns (a water
  /// fluid writes both): below 0 when energy left (damping, dissipation), above 0 when the
  /// run made energy (the sign of an instability); NaN without kinetic energy columns.
  double energy_change = 0.0;
  std::vector<double> errors;  ///< one per spec measure; NaN where it could not be taken
  double seconds_per_step() const { return steps > 0 ? run_seconds / steps : 0.0; }
};

/// Fills `record` from the child's outcome and the run folder it left (run.json,
/// metrics.csv); measures are taken from completed runs only. Never throws for what the
/// run left: a missing or damaged file is recorded in the message.
void record_run(const BenchSpec& spec, const ChildOutcome& child,
                const std::filesystem::path& run_dir, const std::filesystem::path& log,
                RunRecord& record);

}  // namespace shellflow::bench
