#include "python_script.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "preview_movie.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::app {

namespace fs = std::filesystem;

int run_python_script(const std::string& name, const std::vector<std::string>& script_args) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share/shellflow" / name);
  candidates.emplace_back(fs::path(SHELLFLOW_SOURCE_SCRIPTS_DIR) / name);
  fs::path script;
  for (const auto& c : candidates)
    if (fs::is_regular_file(c, ec)) {
      script = c;
      break;
    }
  if (script.empty())
    throw IoError("cannot find " + name + " (looked in " + candidates.front().string() + " and " +
                  candidates.back().string() + ")");
  std::string python;
  if (const char* env = std::getenv("SHELLFLOW_PYTHON"); env && *env)
    python = env;
  else if (::access("/usr/bin/python3", X_OK) == 0)
    python = "/usr/bin/python3";  // where Debian's python3-matplotlib is
  else
    python = find_on_path("python3").string();
  if (python.empty())
    throw IoError("python3 is not on PATH: install python3 and python3-matplotlib");
  std::vector<std::string> args = {python, script.string()};
  args.insert(args.end(), script_args.begin(), script_args.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execv(argv[0], argv.data());
    std::fprintf(stderr, "error: cannot run %s: %s\n", argv[0], std::strerror(errno));
    ::_exit(127);
  }
  int status = 0;
  if (pid < 0 || ::waitpid(pid, &status, 0) < 0)
    throw IoError(std::string("cannot start python3: ") + std::strerror(errno));
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace shellflow::app
