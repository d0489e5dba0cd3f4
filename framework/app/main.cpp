// The `shellflow` command line: run, validate and list plugins.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "shellflow/runtime/plugin_docs.hpp"
#include "shellflow/runtime/plugin_registry.hpp"
#include "shellflow/runtime/progress.hpp"
#include "shellflow/runtime/run_driver.hpp"
#include "shellflow/runtime/scene.hpp"
#include "shellflow/sdk/error.hpp"

namespace {

namespace rt = shellflow::runtime;

// Exit codes, documented in README.
constexpr int kExitOk = 0;
constexpr int kExitInputError = 1;  // bad scene, plugin or output folder
constexpr int kExitNumerical = 3;   // the simulation produced a non-finite value
constexpr int kExitInterrupted = 130;

std::atomic<bool> g_stop_requested{false};

extern "C" void on_interrupt(int) {
  // First Ctrl-C: finish the step and write the frame; a second one ends the process.
  g_stop_requested.store(true);
  std::signal(SIGINT, SIG_DFL);
}

int run_command(const std::string& scene_file, std::optional<int> frames,
                std::optional<std::string> out, bool overwrite, int checkpoint_every, bool resume) {
  const auto scene = rt::load_scene(scene_file);
  rt::RunOptions options;
  options.frames = frames;
  if (out) options.out = *out;
  options.overwrite = overwrite;
  options.checkpoint_every = checkpoint_every;
  options.resume = resume;
  rt::ProgressPrinter printer(stderr);
  options.on_progress = [&](const rt::Progress& p) { printer.update(p); };
  options.stop_requested = &g_stop_requested;
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  const auto summary = rt::run_scene(scene, options);
  printer.finish();
  switch (summary.status) {
    case rt::RunStatus::Completed:
      spdlog::info("wrote {} frames to {} ({} steps, {:.2f} s, {:.3f} s/frame)",
                   summary.frames_written, summary.out_dir.string(), summary.steps,
                   summary.wall_seconds,
                   summary.last_frame > 0 ? summary.wall_seconds / summary.last_frame : 0.0);
      return kExitOk;
    case rt::RunStatus::Interrupted:
      spdlog::warn("{}", summary.message);
      return kExitInterrupted;
    default:
      spdlog::error("{}", summary.message);
      return kExitNumerical;
  }
}

int validate_command(const std::string& scene_file) {
  // A dry run: the scene's schema, then every plugin constructed as `run` constructs it
  // (the same function, so the same refusals and messages); nothing is written and no
  // step is taken.
  const auto scene = rt::load_scene(scene_file);
  rt::construct_plugins(scene);
  std::printf("%s: valid scene '%s' (%s%zu solids, %zu outputs, %d frames at %g fps)\n",
              scene.file.c_str(), scene.name.c_str(), scene.fluid ? "a fluid, " : "no fluid, ",
              scene.solids.size(), scene.outputs.size(), scene.time.frames, scene.time.fps);
  return kExitOk;
}

int plugins_command(bool verbose) {
  rt::PluginRegistry registry(rt::PluginRegistry::default_search_dirs());
  std::printf("Plugin search path:\n");
  for (const auto& d : registry.search_dirs()) std::printf("  %s\n", d.c_str());
  for (const auto& c : registry.candidates()) {
    if (!c.library) {
      std::printf("\n[unusable] %s\n  %s\n", c.file.c_str(), c.error.c_str());
      continue;
    }
    const auto& lib = *c.library;
    std::printf("\n%s (%s plugin, version %s)\n  file: %s\n", lib.name().c_str(),
                rt::to_string(lib.kind()).c_str(), lib.version().c_str(), c.file.c_str());
    if (!c.error.empty()) std::printf("  ERROR: %s\n", c.error.c_str());
    if (!c.shadowed_by.empty()) {
      std::printf("  shadowed by %s (earlier on the search path)\n", c.shadowed_by.c_str());
      continue;
    }
    if (lib.schema().json().contains("doc"))
      std::printf("  %s\n", lib.schema().json()["doc"].get<std::string>().c_str());
    if (verbose) std::printf("%s", rt::format_schema_docs(lib.schema().json(), 4).c_str());
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("shellflow"));
  spdlog::set_pattern("%^[%l]%$ %v");

  CLI::App app{
      "shellflow: smoke and water two-way coupled to thin shells (Guendelman et al. 2005)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", SHELLFLOW_VERSION);

  std::string scene_file;
  std::optional<int> frames;
  std::optional<std::string> out;
  bool overwrite = false;
  auto* run = app.add_subcommand("run", "simulate a scene and write out/<scene>/");
  run->add_option("scene", scene_file, "scene JSON file")->required();
  run->add_option("--frames", frames, "frames to simulate (default: the scene's /time/frames)")
      ->check(CLI::PositiveNumber);
  run->add_option("--out", out, "output folder (default: out/<scene name>)");
  auto* overwrite_flag =
      run->add_flag("--overwrite", overwrite, "replace the run already in the output folder");
  int checkpoint_every = 10;
  bool resume = false;
  run->add_option("--checkpoint-every", checkpoint_every,
                  "write a checkpoint every N frames into <out>/checkpoints/, keeping the last "
                  "two (0: only on Ctrl-C)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--resume", resume,
                "continue the interrupted or crashed run in the output folder from its newest "
                "readable checkpoint (refused if the scene or the plugins changed)")
      ->excludes(overwrite_flag);

  auto* validate = app.add_subcommand(
      "validate", "check a scene and construct its plugins as run does, writing nothing");
  validate->add_option("scene", scene_file, "scene JSON file")->required();

  bool brief = false;
  auto* plugins = app.add_subcommand("plugins", "list the plugins found and their parameters");
  plugins->add_flag("--brief", brief, "names only, no parameter docs");

  CLI11_PARSE(app, argc, argv);
  try {
    if (run->parsed())
      return run_command(scene_file, frames, out, overwrite, checkpoint_every, resume);
    if (validate->parsed()) return validate_command(scene_file);
    if (plugins->parsed()) return plugins_command(!brief);
  } catch (const shellflow::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitInputError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 2;
  }
  return kExitOk;
}
