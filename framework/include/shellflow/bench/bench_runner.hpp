#pragma once
// `shellflow bench`: every run of a spec as its own child `shellflow run` (a blow-up or a
// crash is a recorded outcome, the sweep goes on), then results.csv and results.md.
//
// The bench folder (default out/bench/<name>/):
//   bench.json           the spec echoed, its status, the run list
//   scenes/<run>.json    the scene each run ran (absolute file paths)
//   runs/<run>/          each run's own folder (run.json, metrics.csv)
//   logs/<run>.log       each run's terminal output
//   results.csv, results.md, plots/ (drawn afterwards by scripts/plot_bench.py)

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include "shellflow/bench/bench_spec.hpp"
#include "shellflow/bench/run_record.hpp"

namespace shellflow::bench {

struct BenchOptions {
  std::filesystem::path out;                ///< the bench folder
  int jobs = 1;                             ///< runs at once (1 for timings that mean something)
  bool overwrite = false;                   ///< replace a bench already in `out`
  std::filesystem::path executable;         ///< the `shellflow` to run each scene with
  std::FILE* progress = stderr;             ///< "run k of n ... ETA" lines; null: quiet
  const std::atomic<bool>* stop = nullptr;  ///< set by Ctrl-C: start no further run
};

/// Makes `dir` ready for a bench: created, or emptied when `overwrite` and it holds one
/// (bench.json). A non-empty folder that holds no bench is never touched.
/// @throw IoError saying what is there and what to do.
void prepare_bench_folder(const std::filesystem::path& dir, bool overwrite);

/// Plans (every scene checked first), runs and records the sweep; writes the files above
/// (results after each run, so a stopped bench keeps what it measured).
/// @throw SceneValidationError for a bad sweep, IoError for the folder.
std::vector<RunRecord> run_bench(const BenchSpec& spec, const BenchOptions& options);

}  // namespace shellflow::bench
