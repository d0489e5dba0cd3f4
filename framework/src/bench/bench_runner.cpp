#include "shellflow/bench/bench_runner.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

#include "shellflow/bench/bench_report.hpp"
#include "shellflow/bench/finest_reference.hpp"
#include "shellflow/bench/sweep_plan.hpp"
#include "shellflow/runtime/output_folder.hpp"
#include "shellflow/runtime/progress.hpp"
#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::bench {

using runtime::clock_text;

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

Json spec_echo(const BenchSpec& spec, const std::vector<SweepPoint>& points,
               const BenchOptions& options) {
  Json j;
  j["bench"] = spec.name;
  j["spec_file"] = spec.file.string();
  j["scene_file"] = spec.scene_file.string();
  j["description"] = spec.description;
  if (spec.frames) j["frames"] = *spec.frames;
  j["jobs"] = options.jobs;
  // What the timings depend on besides the code: threads per run and how busy the machine
  // was when the bench started.
  const char* threads = std::getenv("OMP_NUM_THREADS");
  j["omp_num_threads"] = threads ? threads : "unset (all cores)";
  std::ifstream loadavg("/proc/loadavg");
  double load = 0.0;
  if (loadavg >> load) j["load_average_at_start"] = load;
  j["axes"] = Json::array();
  for (const auto& a : spec.axes)
    j["axes"].push_back({{"pointer", a.pointer},
                         {"label", a.label},
                         {"spacing", to_string(a.spacing)},
                         {"values", a.values}});
  j["measures"] = Json::array();
  for (const auto& m : spec.measures)
    j["measures"].push_back({{"label", m.label}, {"measure", m.measure}, {"params", m.params}});
  j["runs"] = Json::array();
  for (const auto& p : points) j["runs"].push_back({{"id", p.id}, {"values", p.values}});
  return j;
}

void write_json(const fs::path& file, const Json& j) {
  sdk::write_file_atomically(file, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

}  // namespace

void prepare_bench_folder(const fs::path& dir, bool overwrite) {
  static const runtime::OutputFolderKind kind{"bench", "bench folder", "bench.json",
                                              "its results.csv"};
  runtime::prepare_output_folder(dir, overwrite, kind);
  std::error_code ec;
  for (const char* sub : {"scenes", "runs", "logs"}) {
    fs::create_directories(dir / sub, ec);
    if (ec) throw IoError("cannot create " + (dir / sub).string() + ": " + ec.message());
  }
}

std::vector<RunRecord> run_bench(const BenchSpec& spec, const BenchOptions& options) {
  // Every scene is checked before the folder is touched or anything runs.
  const std::vector<SweepPoint> points = plan_sweep(spec);
  prepare_bench_folder(options.out, options.overwrite);
  Json echo = spec_echo(spec, points, options);
  echo["status"] = "running";
  write_json(options.out / "bench.json", echo);

  std::vector<ChildCommand> commands;
  for (const auto& p : points) {
    const fs::path scene_file = options.out / "scenes" / (p.id + ".json");
    write_json(scene_file, p.scene);
    ChildCommand c;
    c.argv = {options.executable.string(),
              "run",
              scene_file.string(),
              "--out",
              (options.out / "runs" / p.id).string(),
              "--checkpoint-every",
              "0"};
    if (spec.frames) {
      c.argv.push_back("--frames");
      c.argv.push_back(std::to_string(*spec.frames));
    }
    c.log = options.out / "logs" / (p.id + ".log");
    commands.push_back(std::move(c));
  }

  std::vector<RunRecord> records(points.size());
  std::vector<bool> done(points.size(), false);
  for (size_t i = 0; i < points.size(); ++i) records[i].point = points[i];
  const auto start = std::chrono::steady_clock::now();
  size_t finished = 0;
  const auto finished_records = [&] {
    std::vector<RunRecord> out;
    for (size_t i = 0; i < records.size(); ++i)
      if (done[i]) out.push_back(records[i]);
    compare_with_finest(spec, out);  // against the finest run finished so far
    return out;
  };
  run_child_processes(
      commands, options.jobs, nullptr,
      [&](size_t i, const ChildOutcome& outcome) {
        record_run(spec, outcome, options.out / "runs" / points[i].id, commands[i].log, records[i]);
        done[i] = true;
        ++finished;
        const auto kept = finished_records();
        write_results_csv(options.out / "results.csv", spec, kept);
        if (options.progress) {
          const double elapsed =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          const double eta = elapsed / finished * (points.size() - finished);
          // As results.csv has it: an against_finest value compared with the finest run so
          // far (empty for that run itself), not the raw column value.
          const RunRecord* shown = &records[i];
          for (const auto& k : kept)
            if (k.point.id == points[i].id) shown = &k;
          const RunRecord& r = *shown;
          std::string errors;
          for (size_t m = 0; m < spec.measures.size(); ++m)
            if (!std::isnan(r.errors[m]))
              errors += "  " + spec.measures[m].label + " " + [&] {
                char b[32];
                std::snprintf(b, sizeof b, "%.3g", r.errors[m]);
                return std::string(b);
              }();
          std::fprintf(options.progress,
                       "run %zu of %zu (%s: %s): %s, %.2f s (run %.2f s), %lld steps, %.0f MB%s  "
                       "ETA %s\n",
                       finished, points.size(), points[i].id.c_str(),
                       describe_point(spec, points[i]).c_str(), to_string(r.outcome).c_str(),
                       r.wall_seconds, r.run_seconds, r.steps, r.peak_mb, errors.c_str(),
                       clock_text(eta).c_str());
          if (r.outcome != RunOutcome::Completed)
            std::fprintf(options.progress, "    %s (log: %s)\n", r.message.c_str(),
                         commands[i].log.c_str());
          std::fflush(options.progress);
        }
      },
      options.stop);

  const auto kept = finished_records();
  write_results_csv(options.out / "results.csv", spec, kept);
  char conditions[160];
  std::snprintf(conditions, sizeof conditions,
                "Timed with OMP_NUM_THREADS=%s, %d run%s at a time, load average %.1f at the "
                "start.",
                echo["omp_num_threads"].get<std::string>().c_str(), options.jobs,
                options.jobs == 1 ? "" : "s", echo.value("load_average_at_start", 0.0));
  write_results_markdown(options.out / "results.md", spec, kept, conditions);
  echo["status"] = kept.size() == points.size() ? "completed" : "interrupted";
  echo["runs_finished"] = kept.size();
  write_json(options.out / "bench.json", echo);
  return kept;
}

}  // namespace shellflow::bench
