#include "shellflow/runtime/run_driver.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <memory>

#include "shellflow/coupling/coupling_loop.hpp"
#include "shellflow/runtime/checkpoint.hpp"
#include "shellflow/runtime/metrics_csv.hpp"
#include "shellflow/runtime/openmp_wait_policy.hpp"
#include "shellflow/runtime/output_folder.hpp"
#include "shellflow/runtime/plugin_instance.hpp"
#include "shellflow/runtime/schema_validator.hpp"
#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using coupling::Clock;
using coupling::seconds_since;

std::string to_string(RunStatus status) {
  switch (status) {
    case RunStatus::Completed:
      return "completed";
    case RunStatus::Interrupted:
      return "interrupted";
    case RunStatus::NumericalFailure:
      return "numerical_failure";
    case RunStatus::Failed:
      return "failed";
  }
  return "unknown";
}

namespace {

std::string now_iso8601() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

/// The first non-finite position or velocity among the shells, described.
std::optional<std::string> find_nonfinite(sdk::ShellSet shells) {
  for (const auto& s : shells) {
    for (int i = 0; i < s.node_count(); ++i) {
      if (!s.positions.row(i).allFinite())
        return "shell '" + s.name + "' node " + std::to_string(i) + " position";
      if (s.velocities.rows() > i && !s.velocities.row(i).allFinite())
        return "shell '" + s.name + "' node " + std::to_string(i) + " velocity";
    }
  }
  return std::nullopt;
}

/// The fastest node among the shells and the fastest fluid sample (the "velocity" field),
/// described, when one exceeds `max_speed` (the stability guard of the §6 loop).
std::optional<std::string> find_runaway(sdk::ShellSet shells, const sdk::FluidSolver* fluid,
                                        double max_speed) {
  for (const auto& s : shells) {
    if (s.velocities.rows() == 0) continue;
    Eigen::Index node = 0;
    const double speed = s.velocities.rowwise().norm().maxCoeff(&node);
    if (speed > max_speed) {
      const double sigma = s.surface_density.size() > 0 ? s.surface_density.minCoeff() : 0.0;
      return "shell '" + s.name + "' node " + std::to_string(node) + " moves at " +
             std::to_string(speed) + " m/s, above /coupling/max_speed = " +
             std::to_string(max_speed) + " m/s. Likely cause: the time step is too large for " +
             "the shell's stiffness, or for the density ratio of a light shell (surface "
             "density " + std::to_string(sigma) + " kg/m^2) against the fluid: lower "
             "/time/max_dt or /time/cfl";
    }
  }
  if (!fluid) return std::nullopt;
  for (const auto& field : fluid->fields()) {
    if (field.name != "velocity" || field.components != 3) continue;
    const std::int64_t n = std::int64_t{field.dims[0]} * field.dims[1] * field.dims[2];
    double max2 = 0.0;
    std::int64_t where = 0;
    for (std::int64_t i = 0; i < n; ++i) {
      const double s2 = field.data[0][i] * field.data[0][i] + field.data[1][i] * field.data[1][i] +
                        field.data[2][i] * field.data[2][i];
      if (s2 > max2) {
        max2 = s2;
        where = i;
      }
    }
    if (std::sqrt(max2) > max_speed)
      return "the fluid moves at " + std::to_string(std::sqrt(max2)) + " m/s at sample " +
             std::to_string(where) + " of its velocity field, above /coupling/max_speed = " +
             std::to_string(max_speed) + " m/s. Likely cause: a time step too large for the "
             "density ratio between a two-way shell and the fluid (lower /time/max_dt or "
             "/time/cfl), or a source or inflow faster than intended";
  }
  return std::nullopt;
}

/// What the run plan enables and why (DESIGN.md: skip what a scene does not need).
Json run_plan(const Scene& scene, sdk::ShellSet shells, const sdk::FluidSolver* fluid_solver) {
  bool two_way = false;
  for (const auto& s : shells) two_way = two_way || s.receives_fluid_forces;
  const bool fluid = scene.fluid.has_value();
  const bool solids = !scene.solids.empty();
  Json plan = Json::array();
  const auto add = [&](const char* module, bool on, const std::string& why) {
    plan.push_back({{"module", module}, {"enabled", on}, {"why", why}});
  };
  add("fluid", fluid,
      fluid ? "\"fluid\" names " + scene.fluid->library->name() : "the scene has no \"fluid\"");
  add("solids", solids,
      std::to_string(scene.solids.size()) + " entries in \"solids\", " +
          std::to_string(shells.size()) + " shells");
  add("shell_visibility", fluid && !shells.empty(),
      fluid && !shells.empty()
          ? "a fluid meets shells: ray casts and invalidation in the shell band"
          : "no ray casts: " + std::string(fluid ? "no shells" : "no fluid"));
  add("two_way_coupling", fluid && two_way,
      !fluid    ? "no fluid"
      : two_way ? "some shells receive fluid forces (§5.1)"
                : "every shell is kinematic: one-way");
  add("look_ahead", fluid && solids,
      fluid && solids ? "solids run one step ahead of the fluid (§6)"
                      : "not needed without both halves");
  add("writers", !scene.outputs.empty(),
      std::to_string(scene.outputs.size()) + " entries in \"outputs\"");
  const auto environment = process_environment();
  add("openmp_bounded_spin", bounded_spin_in_effect(environment),
      describe_openmp_wait_policy(environment));
  if (fluid_solver != nullptr)
    for (const auto& e : fluid_solver->plan()) add(e.module.c_str(), e.enabled, e.why);
  return plan;
}

/// What makes the run in run.json (`before`) another run than the one about to start
/// (`now`): the resolved scene, the plugins and their versions, shellflow and its build.
std::vector<std::string> resume_differences(const Json& before, const Json& now) {
  std::vector<std::string> out;
  const auto short_dump = [](const Json& j) {
    std::string s = j.dump();
    return s.size() > 80 ? s.substr(0, 77) + "..." : s;
  };
  for (const char* key : {"shellflow_version", "plugin_abi", "build_signature"}) {
    const Json was = before.value(key, Json());
    if (was != now.at(key))
      out.push_back(std::string(key) + " was " + short_dump(was) + ", now " +
                    short_dump(now.at(key)));
  }
  const Json plugins_before = before.value("plugins", Json::array());
  const auto& plugins_now = now.at("plugins");
  for (size_t i = 0; i < std::max(plugins_before.size(), plugins_now.size()); ++i) {
    const auto describe = [](const Json& p) {
      return p.value("role", std::string()) + " '" + p.value("name", std::string()) + "' (" +
             p.value("plugin", std::string()) + " " + p.value("version", std::string()) + ")";
    };
    if (i >= plugins_before.size()) {
      out.push_back("plugin added: " + describe(plugins_now[i]));
    } else if (i >= plugins_now.size()) {
      out.push_back("plugin removed: " + describe(plugins_before[i]));
    } else {
      bool same = true;
      for (const char* k : {"role", "name", "plugin", "version"})
        same = same && plugins_before[i].value(k, Json()) == plugins_now[i].at(k);
      if (!same)
        out.push_back("plugin " + describe(plugins_before[i]) + " is now " +
                      describe(plugins_now[i]));
    }
  }
  const Json config_before = before.value("config", Json());
  for (const auto& op : Json::diff(config_before, now.at("config"))) {
    const std::string path = op.at("path").get<std::string>();
    const Json::json_pointer pointer(path);
    const std::string what = op.at("op").get<std::string>();
    if (what == "add") {
      out.push_back("scene " + path + " added: " + short_dump(op.at("value")));
    } else if (what == "remove") {
      out.push_back("scene " + path + " removed (was " + short_dump(config_before.at(pointer)) +
                    ")");
    } else {
      out.push_back("scene " + path + " was " + short_dump(config_before.at(pointer)) + ", now " +
                    short_dump(op.at("value")));
    }
  }
  return out;
}

}  // namespace

ScenePlugins construct_plugins(const Scene& scene) {
  ScenePlugins plugins;
  std::vector<ValidationIssue> issues;
  // Each refusal is kept with its path and its message as run would print it.
  const auto attempt = [&](const auto& create) {
    try {
      create();
    } catch (const SceneError& e) {
      issues.push_back({e.json_path(), e.detail()});
    }
  };
  if (scene.fluid) attempt([&] { plugins.fluid = create_fluid(scene, *scene.fluid); });
  for (const auto& spec : scene.solids)
    attempt([&] { plugins.solids.push_back(create_solid(scene, spec)); });
  for (const auto& spec : scene.outputs)
    attempt([&] { plugins.writers.push_back(create_writer(scene, spec)); });
  if (issues.empty()) {
    std::vector<sdk::SolidSolver*> solid_ptrs;
    for (auto& s : plugins.solids) solid_ptrs.push_back(s.get());
    const coupling::CouplingLoop loop(nullptr, solid_ptrs, {});
    if (auto dup = loop.duplicate_surface_name())
      issues.push_back({"/solids", "two shells are both named '" + *dup +
                                       "'; give the solids different \"name\"s"});
  }
  if (!issues.empty()) throw SceneValidationError(scene.file.string(), std::move(issues));
  return plugins;
}

RunSummary run_scene(const Scene& scene, const RunOptions& options) {
  const auto wall_start = Clock::now();
  const int frames = options.frames.value_or(scene.time.frames);
  if (frames < 1) throw Error("--frames must be at least 1, got " + std::to_string(frames));
  const double frame_dt = 1.0 / scene.time.fps;

  // Everything that can fail on bad input happens before the output folder is touched,
  // in the one function `shellflow validate` calls too.
  ScenePlugins instances = construct_plugins(scene);
  auto& fluid = instances.fluid;
  auto& solids = instances.solids;
  auto& writers = instances.writers;

  std::vector<sdk::SolidSolver*> solid_ptrs;
  for (auto& s : solids) solid_ptrs.push_back(s.get());
  coupling::CouplingLoop loop(fluid ? fluid->get() : nullptr, solid_ptrs,
                              {scene.time.cfl, scene.time.max_dt});

  RunSummary summary;
  summary.out_dir = options.out.value_or(fs::path("out") / scene.name);
  if (options.resume && options.overwrite)
    throw Error("--resume continues the run in " + summary.out_dir.string() +
                " and --overwrite replaces it: give one of them");
  if (!options.resume) prepare_output_folder(summary.out_dir, options.overwrite);

  Json run;
  run["scene"] = scene.name;
  run["scene_file"] = scene.file.string();
  run["shellflow_version"] = SHELLFLOW_VERSION;
  run["plugin_abi"] =
      std::to_string(SHELLFLOW_ABI_MAJOR) + "." + std::to_string(SHELLFLOW_ABI_MINOR);
  run["build_signature"] = runtime_build_signature();
  run["started"] = now_iso8601();
  run["status"] = "running";
  run["frames_requested"] = frames;
  run["fps"] = scene.time.fps;
  Json plugins = Json::array();
  const auto describe = [&](const std::string& role, const PluginSpec& spec) {
    plugins.push_back({{"role", role},
                       {"name", spec.instance_name},
                       {"plugin", spec.library->name()},
                       {"version", spec.library->version()},
                       {"file", spec.library->file().string()}});
  };
  if (scene.fluid) describe("fluid", *scene.fluid);
  for (const auto& s : scene.solids) describe("solid", s);
  for (const auto& s : scene.outputs) describe("writer", s);
  run["plugins"] = plugins;
  run["config"] = scene.resolved;
  const fs::path run_json = summary.out_dir / "run.json";

  // Resume: the run in the folder must be this scene with these plugins; its newest
  // checkpoint that reads and restores is where it continues. Nothing is written before.
  std::optional<Checkpoint> resumed;
  if (options.resume) {
    const std::string where = summary.out_dir.string();
    if (!fs::exists(run_json))
      throw IoError("cannot resume: " + where +
                    " holds no run (no run.json); run the scene "
                    "without --resume to start it");
    Json before;
    try {
      std::ifstream in(run_json);
      before = Json::parse(in);
    } catch (const std::exception& e) {
      throw IoError("cannot resume: " + run_json.string() + " cannot be read: " + e.what());
    }
    const auto differences = resume_differences(before, run);
    if (!differences.empty()) {
      std::string list;
      for (const auto& d : differences) list += "\n  " + d;
      throw Error("cannot resume the run in " + where +
                  ": it was started with another scene "
                  "or other plugins (" +
                  scene.file.string() + " against " + run_json.string() + "):" + list +
                  "\nUndo the change, or start afresh with --overwrite");
    }
    std::string skipped;
    for (const auto& file : list_checkpoints(summary.out_dir)) {
      try {
        Checkpoint c = read_checkpoint(file);
        sdk::StateReader in(c.state);
        loop.restore(in);
        sdk::StateBuffer().swap(c.state);  // the solvers hold it now: free it for the run
        resumed = std::move(c);
        break;
      } catch (const Error& e) {
        spdlog::warn("skipping checkpoint {}: {}", file.string(), e.what());
        skipped += "\n  " + file.filename().string() + ": " + e.what();
      }
    }
    if (!resumed)
      throw IoError("cannot resume the run in " + where + ": no readable checkpoint in " +
                    checkpoint_folder(summary.out_dir).string() +
                    (skipped.empty() ? std::string(" (there is none)") : ":" + skipped) +
                    "\nStart afresh with --overwrite");
    // Checkpoints after the one resumed from belong to the abandoned continuation (or are
    // the damaged ones skipped): remove them so that only this run's stay.
    for (const auto& file : list_checkpoints(summary.out_dir)) {
      if (file == resumed->file) break;
      std::error_code ec;
      fs::remove(file, ec);
    }
    summary.resumed_from_step = resumed->meta.step;
    summary.steps = resumed->meta.step;
    summary.frames_written = resumed->meta.frames_written;
    summary.last_frame = resumed->meta.last_frame;
    spdlog::info("resuming {} from {} (step {}, t = {} s)", where, resumed->file.string(),
                 resumed->meta.step, resumed->meta.time);
    const Json plan = before.value("plan", Json());
    Json history = before.value("resumed", Json::array());
    history.push_back({{"at", now_iso8601()},
                       {"checkpoint", resumed->file.filename().string()},
                       {"step", resumed->meta.step},
                       {"time", resumed->meta.time}});
    run["started"] = before.value("started", run["started"]);
    run["resumed"] = history;
    if (!plan.is_null()) run["plan"] = plan;
  }
  sdk::write_file_atomically(run_json, [&](std::ostream& out) { out << run.dump(2) << "\n"; });

  std::optional<MetricsCsv> metrics_storage;
  if (resumed)
    metrics_storage.emplace(summary.out_dir / "metrics.csv", resumed->meta.metrics_rows);
  else
    metrics_storage.emplace(summary.out_dir / "metrics.csv");
  MetricsCsv& metrics = *metrics_storage;
  const sdk::RunInfo info{summary.out_dir, scene.name, scene.time.fps};
  for (auto& w : writers) w->begin(info);

  double write_seconds = 0.0;
  const auto write_frame = [&](int frame) {
    const auto t0 = Clock::now();
    const sdk::FrameView view{frame, loop.time(), loop.shells(), fluid ? fluid->get() : nullptr};
    for (auto& w : writers) w->write_frame(view);
    write_seconds += seconds_since(t0);
    summary.frames_written += 1;
    summary.last_frame = frame;
  };

  const auto finish_run_json = [&] {
    summary.sim_time = loop.time();
    summary.wall_seconds = seconds_since(wall_start);
    run["status"] = to_string(summary.status);
    if (!summary.message.empty()) run["message"] = summary.message;
    run["finished"] = now_iso8601();
    run["frames_written"] = summary.frames_written;
    run["last_frame"] = summary.last_frame;
    run["last_frame_time"] = summary.sim_time;
    run["steps"] = summary.steps;
    run["wall_seconds"] = summary.wall_seconds;
    run["seconds_per_frame"] =
        summary.last_frame > 0 ? summary.wall_seconds / summary.last_frame : 0.0;
    run["metrics_columns"] = metrics.columns();
    sdk::write_file_atomically(run_json, [&](std::ostream& out) { out << run.dump(2) << "\n"; });
  };

  // The whole state, with the counters a resumed run starts from (`next_frame`: the frame
  // the loop works on next, the current one when stopped within it).
  const auto save_checkpoint = [&](int next_frame) {
    CheckpointMeta meta;
    meta.step = summary.steps;
    meta.next_frame = next_frame;
    meta.time = loop.time();
    meta.frames_written = summary.frames_written;
    meta.last_frame = summary.last_frame;
    meta.metrics_rows = summary.steps;  // one row per step
    write_checkpoint(summary.out_dir, meta, [&](sdk::StateWriter& out) { loop.save(out); });
  };

  try {
    int first_frame = 1;
    if (resumed) {
      first_frame = resumed->meta.next_frame;
    } else {
      loop.start(0.0, frame_dt);
      run["plan"] = run_plan(scene, loop.shells(), fluid ? fluid->get() : nullptr);
      write_frame(0);
    }

    sdk::Metrics reported;
    std::optional<std::string> stop_reason;
    for (int frame = first_frame; frame <= frames && !stop_reason; ++frame) {
      const auto frame_start = Clock::now();
      const double frame_end = frame * frame_dt;
      // Steps end exactly on the frame time (to round-off relative to it).
      while (frame_end - loop.time() > 1e-12 * frame_end) {
        const double remaining = frame_end - loop.time();
        const double dt = loop.next_dt(remaining);
        if (!(dt > 0.0) || !std::isfinite(dt))
          throw NumericalError("step " + std::to_string(summary.steps + 1) +
                               " at t = " + std::to_string(loop.time()) +
                               " s: the solvers asked for a time step of " + std::to_string(dt) +
                               " s");
        const double after = remaining - dt > 1e-12 * frame_end ? remaining - dt : frame_dt;
        const auto phases = loop.step(dt, after);
        summary.steps += 1;
        write_seconds = 0.0;

        std::vector<std::pair<std::string, double>> row = {
            {"step", double(summary.steps)}, {"frame", double(frame)},
            {"time", loop.time()},           {"dt", dt},
            {"t_advect", phases.advect},     {"t_coupling_forces", phases.coupling_forces},
            {"t_solids", phases.solids},     {"t_project", phases.project}};
        const auto collect = [&](const std::string& prefix, const auto& solver) {
          reported.clear();
          solver.report(reported);
          for (const auto& [k, v] : reported.values()) row.emplace_back(prefix + "." + k, v);
        };
        if (fluid) collect(fluid->name(), **fluid);
        for (auto& s : solids) collect(s.name(), *s);
        metrics.write_row(row);

        // Stability guard: stop at the first non-finite value, keeping the frames so far.
        std::optional<std::string> bad = find_nonfinite(loop.shells());
        if (!bad && fluid) bad = (*fluid)->find_nonfinite();
        std::optional<std::string> runaway;
        if (!bad) runaway = find_runaway(loop.shells(), fluid ? fluid->get() : nullptr,
                                         scene.max_speed);
        if (runaway) {
          summary.status = RunStatus::NumericalFailure;
          summary.message = "unstable at step " + std::to_string(summary.steps) + " (t = " +
                            std::to_string(loop.time()) + " s, during frame " +
                            std::to_string(frame) + "): " + *runaway +
                            ". The last good frame is frame " +
                            std::to_string(summary.last_frame) + " in " +
                            summary.out_dir.string();
          stop_reason = summary.message;
          break;
        }
        if (bad) {
          summary.status = RunStatus::NumericalFailure;
          summary.message =
              "non-finite value in " + *bad + " at step " + std::to_string(summary.steps) +
              " (t = " + std::to_string(loop.time()) + " s, during frame " + std::to_string(frame) +
              "); the last good frame is frame " + std::to_string(summary.last_frame) + " in " +
              summary.out_dir.string() +
              ". Likely causes: a time step too large for the stiffness or the density "
              "ratio (lower /time/max_dt), or a bad parameter";
          stop_reason = summary.message;
          break;
        }
        if (options.stop_requested && options.stop_requested->load()) {
          summary.status = RunStatus::Interrupted;
          save_checkpoint(frame);  // before the partial frame: it is not a complete one
          write_frame(frame);  // the current state is good: keep it as a partial frame
          summary.message =
              "interrupted by the user at step " + std::to_string(summary.steps) +
              " (t = " + std::to_string(loop.time()) + " s); frame " + std::to_string(frame) +
              " holds that state (partial frame), earlier frames are complete; "
              "continue with `shellflow run " +
              scene.file.string() + " --resume" +
              (options.out ? " --out " + summary.out_dir.string() : std::string()) + "`";
          stop_reason = summary.message;
          break;
        }
      }
      if (stop_reason) break;
      write_frame(frame);
      if (options.checkpoint_every > 0 &&
          (frame % options.checkpoint_every == 0 || frame == frames))
        save_checkpoint(frame + 1);
      if (options.on_progress) {
        Progress p;
        p.frame = frame;
        p.frames = frames;
        p.sim_time = loop.time();
        p.seconds_per_frame = seconds_since(frame_start);
        p.steps = summary.steps;
        const double elapsed = seconds_since(wall_start);
        p.eta_seconds = elapsed / (frame - first_frame + 1) * (frames - frame);
        options.on_progress(p);
      }
    }
    for (auto& w : writers) w->end();
  } catch (const std::exception& e) {
    // Leave a run.json that says how the run ended; the frames so far stay.
    summary.status = RunStatus::Failed;
    summary.message = std::string(e.what()) + " (the last complete frame is frame " +
                      std::to_string(summary.last_frame) + ")";
    finish_run_json();
    throw;
  }
  finish_run_json();
  return summary;
}

}  // namespace shellflow::runtime
