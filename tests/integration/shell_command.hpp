#pragma once
// Runs a shell command for the CLI tests and returns its exit code and its output
// (stdout and stderr together).

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace shellflow::testing {

struct ShellResult {
  int exit_code;
  std::string output;
};

inline ShellResult run_shell(const std::string& command) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), out};
}

}  // namespace shellflow::testing
