#pragma once
// Peak memory of a benchmark's run, each measured in a fresh child process of the same
// benchmark program (ru_maxrss only grows, so one process per measurement): the child is
// started with `--peak-memory=SPEC`, runs the case, and prints "peak_rss_kb <value>".
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace shellflow::bench {

/// In the child, after the run: prints this process's peak resident set.
inline int print_peak_rss() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak_rss_kb %ld\n", usage.ru_maxrss);
  return 0;
}

/// In the parent: runs this program with `--peak-memory=spec` and records the child's
/// peak resident set as the counter peak_rss_MB.
inline void measure_in_child(benchmark::State& state, const std::string& spec) {
  const std::string command =
      "/proc/" + std::to_string(getpid()) + "/exe --peak-memory=" + spec + " 2>/dev/null";
  long kb = -1;
  for (auto _ : state) {
    FILE* child = popen(command.c_str(), "r");
    if (child == nullptr) {
      state.SkipWithError("popen failed");
      return;
    }
    char line[256];
    while (std::fgets(line, sizeof line, child) != nullptr)
      if (std::sscanf(line, "peak_rss_kb %ld", &kb) == 1) break;
    pclose(child);
  }
  if (kb < 0) {
    state.SkipWithError("the child printed no peak_rss_kb");
    return;
  }
  state.counters["peak_rss_MB"] = kb / 1024.0;
}

}  // namespace shellflow::bench
