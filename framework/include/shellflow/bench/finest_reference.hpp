#pragma once
// Errors against the finest run of a sweep, for measures without an analytic answer
// (ErrorMeasure::against_finest): each run's value is compared with that of the run with
// the smallest h along the first refinement axis ("spacing") among the runs whose other
// axes hold the same values. The reference run's own error is left empty and its message
// says it is the reference.

#include <vector>

#include "shellflow/bench/bench_spec.hpp"
#include "shellflow/bench/run_record.hpp"

namespace shellflow::bench {

/// Replaces the values of every against_finest measure in `records` (completed runs)
/// by |v − v_finest| / |v_finest| (|v − v_finest| when v_finest is 0).
void compare_with_finest(const BenchSpec& spec, std::vector<RunRecord>& records);

}  // namespace shellflow::bench
