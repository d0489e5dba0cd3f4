#pragma once
// The CLI's matplotlib scripts (scripts/plot_run.py, scripts/plot_bench.py): found beside
// an installed shellflow (<prefix>/share/shellflow/) or in the source tree, run with the
// python3 that has Debian's python3-matplotlib.

#include <string>
#include <vector>

namespace shellflow::app {

/// Runs `script` (a file name, e.g. "plot_run.py") with `args`; returns its exit code.
/// @throw IoError when the script or python3 cannot be found or started.
int run_python_script(const std::string& script, const std::vector<std::string>& args);

}  // namespace shellflow::app
