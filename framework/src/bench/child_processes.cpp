#include "shellflow/bench/child_processes.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>

#include "shellflow/sdk/error.hpp"

namespace shellflow::bench {

namespace {

using Clock = std::chrono::steady_clock;

pid_t start_child(const ChildCommand& command) {
  std::vector<std::string> args = command.argv;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int log = ::open(command.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log < 0) throw IoError("cannot create " + command.log.string() + ": " + std::strerror(errno));
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    // In the child: only async-signal-safe calls until exec.
    ::dup2(log, STDOUT_FILENO);
    ::dup2(log, STDERR_FILENO);
    ::execv(argv[0], argv.data());
    const char msg[] = "error: cannot execute the child command\n";
    [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
    ::_exit(127);
  }
  ::close(log);
  return pid;
}

}  // namespace

void run_child_processes(const std::vector<ChildCommand>& commands, int jobs,
                         const std::function<void(size_t)>& on_start,
                         const std::function<void(size_t, const ChildOutcome&)>& on_done,
                         const std::atomic<bool>* stop) {
  if (jobs < 1) jobs = 1;
  struct Running {
    size_t index;
    Clock::time_point start;
  };
  std::map<pid_t, Running> running;
  size_t next = 0;
  const auto stopped = [&] { return stop && stop->load(); };
  while (next < commands.size() || !running.empty()) {
    while (!stopped() && next < commands.size() && static_cast<int>(running.size()) < jobs) {
      if (on_start) on_start(next);
      const auto start = Clock::now();
      const pid_t pid = start_child(commands[next]);
      if (pid < 0) {
        ChildOutcome outcome;
        outcome.exit_code = 127;
        outcome.started = false;
        on_done(next, outcome);
      } else {
        running[pid] = {next, start};
      }
      ++next;
    }
    if (running.empty()) break;  // stopped with nothing left running
    int status = 0;
    rusage usage{};
    const pid_t pid = ::wait4(-1, &status, 0, &usage);
    if (pid < 0) {
      if (errno == EINTR) continue;  // Ctrl-C: the children got it too; reap them
      throw Error(std::string("wait4 failed: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;  // not one of ours
    ChildOutcome outcome;
    outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - it->second.start).count();
    outcome.peak_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: KiB
    if (WIFEXITED(status)) {
      outcome.exit_code = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
      outcome.signal = WTERMSIG(status);
    }
    const size_t index = it->second.index;
    running.erase(it);
    on_done(index, outcome);
  }
}

}  // namespace shellflow::bench
