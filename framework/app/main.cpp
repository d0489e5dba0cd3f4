// The `shellflow` command line: run, validate, list plugins, write a new plugin, make a movie
// or plots of a run, bench a sweep of runs.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "bench_command.hpp"
#include "new_solid.hpp"
#include "preview_movie.hpp"
#include "python_script.hpp"
#include "shellflow/runtime/openmp_wait_policy.hpp"
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

namespace app = shellflow::app;

/// `f` when it is a terminal (a progress line rewritten in place), else null: a log or a
/// pipe gets the summary line only.
std::FILE* terminal_or_null(std::FILE* f) {
  return ::isatty(::fileno(f)) ? f : nullptr;
}

/// The end of a run that wrote previews: preview.mp4, or a one-line note why not. Never
/// changes the run's exit code.
void movie_after_run(const std::filesystem::path& out_dir) {
  try {
    std::error_code ec;
    if (!std::filesystem::exists(out_dir / "run.json", ec)) return;
    const auto movie = app::encode_preview_movie(out_dir, terminal_or_null(stderr));
    switch (movie.status) {
      case app::PreviewMovie::Status::Written:
        spdlog::info("encoded {} previews into {} (H.264, {:g} fps)", movie.frames,
                     movie.file.string(), movie.fps);
        break;
      case app::PreviewMovie::Status::NoFfmpeg:
        spdlog::info("note: {}", movie.message);
        break;
      case app::PreviewMovie::Status::Failed:
        spdlog::warn("{}", movie.message);
        break;
      case app::PreviewMovie::Status::NoPreviews:
        break;
    }
  } catch (const std::exception& e) {
    spdlog::warn("no preview.mp4: {}", e.what());
  }
}

int movie_command(const std::string& run_dir) {
  if (!std::filesystem::is_directory(run_dir))
    throw shellflow::IoError("run folder not found: " + run_dir +
                             " (give the folder a run wrote, as out/<scene name>)");
  const auto movie = app::encode_preview_movie(run_dir, terminal_or_null(stderr));
  if (movie.status != app::PreviewMovie::Status::Written) throw shellflow::IoError(movie.message);
  std::printf("wrote %s: %d previews from %s, H.264, %g fps\n", movie.file.c_str(), movie.frames,
              movie.previews.c_str(), movie.fps);
  return kExitOk;
}

/// `shellflow plot`: scripts/plot_run.py (installed as <prefix>/share/shellflow/plot_run.py)
/// with the python3 that has Debian's python3-matplotlib, arguments passed as given.
int plot_command(const std::string& run_dir, const std::vector<std::string>& columns) {
  std::vector<std::string> args = {run_dir};
  args.insert(args.end(), columns.begin(), columns.end());
  return app::run_python_script("plot_run.py", args) == 0 ? kExitOk : kExitInputError;
}

int run_command(const std::string& scene_file, std::optional<int> frames,
                std::optional<std::string> out, bool overwrite, int checkpoint_every, bool resume) {
  const auto scene = rt::load_scene(scene_file);
  spdlog::info("OpenMP wait policy: {}",
               rt::describe_openmp_wait_policy(rt::process_environment()));
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
  movie_after_run(summary.out_dir);  // also after a failure: the frames before it are useful
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

// The parameter reference of every usable plugin, as Markdown (docs/plugins.md). Nothing
// machine-specific is printed, so that the committed file can be compared with a build's.
int plugins_markdown_command() {
  rt::PluginRegistry registry(rt::PluginRegistry::default_search_dirs());
  std::vector<const rt::PluginCandidate*> usable;
  for (const auto& c : registry.candidates()) {
    if (!c.library || !c.error.empty()) {
      std::fprintf(stderr, "error: %s: %s\n", c.file.c_str(), c.error.c_str());
      return kExitInputError;
    }
    if (c.shadowed_by.empty()) usable.push_back(&c);
  }
  std::sort(usable.begin(), usable.end(), [](const auto* a, const auto* b) {
    return std::pair(rt::to_string(a->library->kind()), a->library->name()) <
           std::pair(rt::to_string(b->library->kind()), b->library->name());
  });
  std::printf(
      "# Plugin parameter reference\n\n"
      "Generated from the plugins' schemas by `shellflow plugins --markdown > docs/plugins.md`;"
      " do not edit by hand (a test fails when this file is stale). A scene names a plugin with"
      " `\"plugin\": \"<name>\"` and gives the parameters below beside it.\n");
  for (const auto* c : usable) {
    const auto& lib = *c->library;
    const auto& schema = lib.schema().json();
    std::printf("\n## %s (%s)\n\n", lib.name().c_str(), rt::to_string(lib.kind()).c_str());
    if (schema.contains("doc")) std::printf("%s\n\n", schema["doc"].get<std::string>().c_str());
    const std::string params = rt::format_schema_markdown(schema);
    std::printf("%s", params.empty() ? "No parameters.\n" : params.c_str());
  }
  return kExitOk;
}

int new_solid_command(const std::string& name, const std::string& dir_arg) {
  const std::string dir = dir_arg.empty() ? name : dir_arg;
  const auto files = shellflow::app::write_new_solid(name, dir);
  std::printf("wrote the solid plugin '%s' into %s/:\n", name.c_str(), dir.c_str());
  for (const auto& f : files) std::printf("  %s\n", f.c_str());
  std::printf(
      "build it against this shellflow and run its scene:\n"
      "  cd %s && cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release"
      " -DCMAKE_PREFIX_PATH=<shellflow install prefix>\n"
      "  cmake --build build && ctest --test-dir build\n"
      "  shellflow run scenes/%s_drop.json\n",
      dir.c_str(), name.c_str());
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("shellflow"));
  spdlog::set_pattern("%^[%l]%$ %v");
  // Before any OpenMP region: a bounded spin unless the user chose a wait policy.
  rt::execute_again_with_bounded_spin(argv);

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
  bool markdown = false;
  plugins->add_flag("--brief", brief, "names only, no parameter docs");
  plugins
      ->add_flag("--markdown", markdown,
                 "the parameter reference as Markdown, as in docs/plugins.md")
      ->excludes("--brief");

  auto* make_new = app.add_subcommand("new", "write a new plugin project from a template");
  make_new->require_subcommand(1);
  std::string new_name, new_dir;
  auto* new_solid = make_new->add_subcommand(
      "solid", "an out-of-tree solid plugin (class, schema, CMakeLists.txt, test, scene)");
  new_solid->add_option("name", new_name, "plugin name: lower-case letters, digits, '_'")
      ->required();
  new_solid->add_option("dir", new_dir, "folder to create, new or empty (default: NAME)");

  std::string run_dir;
  auto* movie = app.add_subcommand(
      "movie", "encode a run's PNG previews into RUN_DIR/preview.mp4 with ffmpeg (H.264)");
  movie->add_option("run_dir", run_dir, "the run's output folder, as out/<scene name>")->required();

  std::vector<std::string> plot_columns;
  auto* plot = app.add_subcommand(
      "plot", "draw metrics.csv columns against time into RUN_DIR/plots/<column>.png");
  plot->add_option("run_dir", run_dir, "the run's output folder, as out/<scene name>")->required();
  plot->add_option("columns", plot_columns,
                   "metrics.csv columns (default: energies, volumes, masses, iterations, "
                   "maximum speeds)");

  app::BenchArguments bench_args;
  auto* bench = app.add_subcommand(
      "bench",
      "sweep a scene (a bench spec's axes), run each point as its own child run, and "
      "write run time, peak memory and errors: results.csv, results.md, plots/");
  bench->add_option("spec", bench_args.spec_file, "bench spec JSON file (configs/bench/)")
      ->required();
  bench->add_option("--out", bench_args.out,
                    "bench folder (default: out/bench/<name>, out/bench/<name>-small)");
  bench
      ->add_option("--jobs", bench_args.jobs,
                   "runs at once (default 1: concurrent runs share the cores and the timings "
                   "mean less)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  bench->add_flag("--small", bench_args.small,
                  "each axis's \"small\" values and the spec's \"small_frames\" (seconds)");
  bench->add_flag("--overwrite", bench_args.overwrite, "replace the bench already in the folder");
  bench->add_flag_function(
      "--no-plots", [&](std::int64_t) { bench_args.plots = false; },
      "write no PNGs (results.csv and results.md only)");

  CLI11_PARSE(app, argc, argv);
  try {
    if (run->parsed())
      return run_command(scene_file, frames, out, overwrite, checkpoint_every, resume);
    if (validate->parsed()) return validate_command(scene_file);
    if (plugins->parsed()) return markdown ? plugins_markdown_command() : plugins_command(!brief);
    if (new_solid->parsed()) return new_solid_command(new_name, new_dir);
    if (movie->parsed()) return movie_command(run_dir);
    if (plot->parsed()) return plot_command(run_dir, plot_columns);
    if (bench->parsed()) {
      std::signal(SIGINT, on_interrupt);  // finish the running runs, start no more
      return app::bench_command(bench_args, &g_stop_requested);
    }
  } catch (const shellflow::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitInputError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return 2;
  }
  return kExitOk;
}
