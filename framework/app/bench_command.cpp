#include "bench_command.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <map>

#include "python_script.hpp"
#include "shellflow/bench/bench_runner.hpp"
#include "shellflow/bench/bench_spec.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::app {

namespace fs = std::filesystem;

int bench_command(const BenchArguments& args, const std::atomic<bool>* stop) {
  const auto spec = bench::load_bench_spec(args.spec_file, args.small);
  bench::BenchOptions options;
  options.out = args.out ? fs::path(*args.out)
                         : fs::path("out") / "bench" / (spec.name + (args.small ? "-small" : ""));
  options.jobs = args.jobs;
  options.overwrite = args.overwrite;
  options.stop = stop;
  std::error_code ec;
  options.executable = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw IoError("cannot find the shellflow executable (/proc/self/exe): " + ec.message());

  const auto records = bench::run_bench(spec, options);
  std::map<std::string, int> outcomes;
  for (const auto& r : records) ++outcomes[bench::to_string(r.outcome)];
  std::string tally;
  for (const auto& [name, n] : outcomes)
    tally += (tally.empty() ? "" : ", ") + std::to_string(n) + " " + name;
  spdlog::info("bench '{}': {} runs ({}) -> {}", spec.name, records.size(), tally,
               (options.out / "results.csv").string());
  if (args.plots) {
    try {
      if (run_python_script("plot_bench.py", {options.out.string()}) != 0)
        spdlog::warn("no plots: scripts/plot_bench.py failed (see above); results.csv stands");
    } catch (const Error& e) {
      spdlog::warn("no plots: {}", e.what());
    }
  }
  return stop && stop->load() ? 130 : 0;
}

}  // namespace shellflow::app
