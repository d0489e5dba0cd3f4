#include "shellflow/bench/sweep_plan.hpp"

#include <algorithm>
#include <cstdio>

#include "shellflow/runtime/scene.hpp"
#include "shellflow/runtime/schema_validator.hpp"

namespace shellflow::bench {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string describe_point(const BenchSpec& spec, const SweepPoint& point) {
  std::string out;
  for (size_t a = 0; a < spec.axes.size(); ++a)
    out += (a ? ", " : "") + spec.axes[a].pointer + " = " + point.values[a].dump();
  return out.empty() ? "the base scene" : out;
}

std::vector<SweepPoint> plan_sweep(const BenchSpec& spec) {
  size_t count = 1;
  for (const auto& axis : spec.axes) count *= axis.values.size();
  std::vector<SweepPoint> points;
  std::vector<runtime::ValidationIssue> issues;
  std::vector<size_t> digit(spec.axes.size(), 0);
  const int width = count >= 1000 ? static_cast<int>(std::to_string(count).size()) : 3;
  for (size_t n = 0; n < count; ++n) {
    // The n-th combination, the last axis fastest.
    for (size_t a = spec.axes.size(), rest = n; a-- > 0;) {
      digit[a] = rest % spec.axes[a].values.size();
      rest /= spec.axes[a].values.size();
    }
    SweepPoint point;
    point.index = static_cast<int>(n + 1);
    char id[32];
    std::snprintf(id, sizeof id, "run_%0*zu", width, n + 1);
    point.id = id;
    Json doc = spec.base_scene;
    for (size_t a = 0; a < spec.axes.size(); ++a) {
      point.values.push_back(spec.axes[a].values[digit[a]]);
      // operator[] creates the keys the file leaves to defaults (load_bench_spec checked
      // that the resolved scene has all but the last).
      doc[Json::json_pointer(spec.axes[a].pointer)] = point.values.back();
    }
    if (!spec.keep_outputs) doc["outputs"] = Json::array();
    doc["name"] = point.id;
    try {
      const auto scene = runtime::parse_scene(doc.dump(), spec.scene_file, spec.plugin_dirs);
      point.scene = scene.resolved;
      // The scene file is written elsewhere: its plugin folders become absolute (files
      // already are, resolved by the validator).
      if (point.scene.contains("plugin_path"))
        for (auto& dir : point.scene["plugin_path"])
          if (fs::path(dir.get<std::string>()).is_relative())
            dir = (spec.scene_file.parent_path() / dir.get<std::string>())
                      .lexically_normal()
                      .string();
    } catch (const runtime::SceneValidationError& e) {
      // A key the scene's schema does not know is the pointer's fault, not the value's:
      // report it once, at the axis's pointer.
      bool pointer_fault = false;
      for (const auto& issue : e.issues())
        for (size_t a = 0; a < spec.axes.size(); ++a)
          if (issue.json_path == spec.axes[a].pointer &&
              issue.message.rfind("unknown key", 0) == 0) {
            pointer_fault = true;
            const std::string path = "/sweep/" + std::to_string(a) + "/pointer";
            const bool reported = std::any_of(issues.begin(), issues.end(),
                                              [&](const auto& i) { return i.json_path == path; });
            if (!reported)
              issues.push_back({path, "the base scene cannot take " + spec.axes[a].pointer + ": " +
                                          issue.message});
          }
      if (pointer_fault) continue;
      std::string detail;
      for (const auto& issue : e.issues())
        detail += "\n    scene " + (issue.json_path.empty() ? "/" : issue.json_path) + ": " +
                  issue.message;
      const std::string path = spec.axes.size() == 1
                                   ? spec.axes[0].values_path + "/" + std::to_string(digit[0])
                                   : std::string("/sweep");
      issues.push_back({path, "with " + describe_point(spec, point) +
                                  " the scene is invalid; change these values:" + detail});
    } catch (const SceneError& e) {
      issues.push_back({"/sweep", "with " + describe_point(spec, point) + ": " + e.detail()});
    }
    points.push_back(std::move(point));
  }
  if (!issues.empty()) throw runtime::SceneValidationError(spec.file.string(), issues);
  return points;
}

}  // namespace shellflow::bench
