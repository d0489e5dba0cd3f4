#pragma once
// `shellflow bench SPEC.json [--out DIR] [--jobs N] [--small] [--overwrite] [--no-plots]`.

#include <atomic>
#include <optional>
#include <string>

namespace shellflow::app {

struct BenchArguments {
  std::string spec_file;
  std::optional<std::string> out;  ///< default out/bench/<name>/ (<name>-small with --small)
  int jobs = 1;
  bool small = false;
  bool overwrite = false;
  bool plots = true;
};

/// Runs the bench and draws its plots; returns the exit code (0 when every run was
/// recorded, whatever its outcome; 130 when Ctrl-C stopped it). @throw shellflow::Error
/// for a bad spec or folder.
int bench_command(const BenchArguments& args, const std::atomic<bool>* stop);

}  // namespace shellflow::app
