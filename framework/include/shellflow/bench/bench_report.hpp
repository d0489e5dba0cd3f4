#pragma once
// What a bench writes about its runs: results.csv (one row per run), results.md (the same
// as a Markdown table, with the observed orders of convergence and what a doubling of
// cost buys), both from the run records.

#include <filesystem>
#include <string>
#include <vector>

#include "shellflow/bench/run_record.hpp"

namespace shellflow::bench {

/// Least-squares slope of log y against log x over the points where both are finite and
/// positive; NaN with fewer than two such points (or one x only).
double log_log_slope(const std::vector<double>& x, const std::vector<double>& y);

/// One fitted line of the convergence table: a measure along a refinement axis, the other
/// axes held at `fixed`.
struct ConvergenceFit {
  std::string measure;  ///< its label
  std::string axis;     ///< the refinement axis's label
  std::string fixed;    ///< "cfl = 0.5" or "" with one axis
  int points = 0;       ///< completed runs with a positive error
  double order = 0.0;   ///< p in error ~ h^p (NaN with fewer than two points)
  /// error ~ wall^s: a doubling of cost multiplies the error by 2^s.
  double cost_slope = 0.0;
};

/// For every measure and every axis with a "spacing".
std::vector<ConvergenceFit> convergence_fits(const BenchSpec& spec,
                                             const std::vector<RunRecord>& records);

/// results.csv: run, each axis, status, exit_code, wall_s (the child process), run_s (the
/// run's own, run.json), steps, s_per_step (run_s / steps), peak_mb, sim_time,
/// energy_change, each measure, message.
void write_results_csv(const std::filesystem::path& file, const BenchSpec& spec,
                       const std::vector<RunRecord>& records);

/// results.md: the table, then the convergence fits. `conditions`: what the timings were
/// taken under (threads, load), one sentence, or "".
void write_results_markdown(const std::filesystem::path& file, const BenchSpec& spec,
                            const std::vector<RunRecord>& records,
                            const std::string& conditions = "");

}  // namespace shellflow::bench
