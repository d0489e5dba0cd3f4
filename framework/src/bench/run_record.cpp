#include "shellflow/bench/run_record.hpp"

#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <limits>

#include "shellflow/bench/error_measures.hpp"
#include "shellflow/bench/run_outputs.hpp"

namespace shellflow::bench {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The last non-empty line of a log: what a run that failed before run.json said.
std::string last_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() > suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

double energy_change(const MetricsTable& metrics) {
  if (metrics.rows() == 0) return kNaN;
  std::vector<double> kinetic(metrics.rows(), 0.0), total(metrics.rows(), 0.0);
  bool any = false;
  for (const auto& c : metrics.columns()) {
    const bool is_kinetic = ends_with(c, ".kinetic_energy");
    if (!is_kinetic && !ends_with(c, ".potential_energy")) continue;
    const auto v = metrics.column(c);
    for (size_t i = 0; i < v.size(); ++i) {
      if (is_kinetic) kinetic[i] += v[i];
      total[i] += v[i];
    }
    any = any || is_kinetic;
  }
  double scale = 0.0;
  for (const double k : kinetic) scale = std::max(scale, k);
  return any && scale > 0.0 ? (total.back() - total.front()) / scale : kNaN;
}

}  // namespace

std::string to_string(RunOutcome outcome) {
  switch (outcome) {
    case RunOutcome::Completed:
      return "completed";
    case RunOutcome::GuardStopped:
      return "guard_stopped";
    case RunOutcome::NonFinite:
      return "non_finite";
    case RunOutcome::Crashed:
      return "crashed";
    default:
      return "failed";
  }
}

void record_run(const BenchSpec& spec, const ChildOutcome& child, const fs::path& run_dir,
                const fs::path& log, RunRecord& record) {
  record.exit_code = child.exit_code;
  record.wall_seconds = child.wall_seconds;
  record.peak_mb = child.peak_rss_mb;
  record.errors.assign(spec.measures.size(), kNaN);
  record.energy_change = kNaN;
  if (child.signal != 0) {
    record.outcome = RunOutcome::Crashed;
    record.message = std::string("killed by signal ") + std::to_string(child.signal) + " (" +
                     strsignal(child.signal) + ")";
  }
  RunOutputs outputs;
  try {
    outputs = RunOutputs::read(run_dir);
  } catch (const Error& e) {
    if (child.signal == 0) {
      record.outcome = RunOutcome::Failed;
      const std::string said = last_line(log);
      record.message = said.empty() ? e.what() : said;
    }
    return;
  }
  record.steps = outputs.run.value("steps", 0LL);
  record.sim_time = outputs.run.value("last_frame_time", 0.0);
  if (outputs.metrics.has("time") && outputs.metrics.rows() > 0)
    record.sim_time = outputs.metrics.column("time").back();
  record.energy_change = energy_change(outputs.metrics);
  record.run_seconds = outputs.run.value("wall_seconds", 0.0);
  if (child.signal != 0) return;
  const std::string status = outputs.run.value("status", "");
  record.message = outputs.run.value("message", "");
  if (status == "completed") {
    record.outcome = RunOutcome::Completed;
  } else if (status == "numerical_failure") {
    // run_driver's two stops: the speed guard ("unstable at step ...") and a non-finite value.
    record.outcome = record.message.rfind("non-finite", 0) == 0 ? RunOutcome::NonFinite
                                                                : RunOutcome::GuardStopped;
  } else {
    record.outcome = RunOutcome::Failed;
    if (record.message.empty()) record.message = "run.json status '" + status + "'";
  }
  if (record.outcome != RunOutcome::Completed) return;
  for (size_t m = 0; m < spec.measures.size(); ++m) {
    const auto& measure = spec.measures[m];
    try {
      record.errors[m] = find_error_measure(measure.measure)->evaluate(outputs, measure.params);
    } catch (const std::exception& e) {
      record.message += (record.message.empty() ? "" : "; ") + measure.label + ": " + e.what();
    }
  }
}

}  // namespace shellflow::bench
