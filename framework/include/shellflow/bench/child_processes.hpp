#pragma once
// Runs commands as child processes, at most `jobs` at a time, each with its output in a
// log file, and reports each one's exit, wall time and peak memory (wait4's rusage). A
// child that crashes or is killed is an outcome like any other, never the end of the
// caller.

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace shellflow::bench {

struct ChildCommand {
  std::vector<std::string> argv;  ///< argv[0]: the program's path
  std::filesystem::path log;      ///< stdout and stderr go here (created, truncated)
};

struct ChildOutcome {
  int exit_code = -1;         ///< when it exited; -1 when a signal ended it
  int signal = 0;             ///< the signal that ended it, 0 when it exited
  double wall_seconds = 0.0;  ///< from fork to reaping
  double peak_rss_mb = 0.0;   ///< ru_maxrss: the child's largest resident set [MiB]
  bool started = true;        ///< false when fork failed (exit_code 127)
};

/// Runs `commands` in order, `jobs` at once. `on_start(i)` before command i starts,
/// `on_done(i, outcome)` as it ends (in the order they end). Once `stop` is set no new
/// command starts (the running ones are waited for; they got the same Ctrl-C).
void run_child_processes(const std::vector<ChildCommand>& commands, int jobs,
                         const std::function<void(size_t)>& on_start,
                         const std::function<void(size_t, const ChildOutcome&)>& on_done,
                         const std::atomic<bool>* stop = nullptr);

}  // namespace shellflow::bench
