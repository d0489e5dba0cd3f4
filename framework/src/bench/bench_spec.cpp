#include "shellflow/bench/bench_spec.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "shellflow/bench/error_measures.hpp"
#include "shellflow/runtime/did_you_mean.hpp"
#include "shellflow/runtime/scene.hpp"
#include "shellflow/runtime/schema_validator.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::bench {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using runtime::pointer_append;
using sdk::Schema;

namespace {

Schema any_value() {
  return Schema::from_json({{"kind", "any"}});
}

Schema axis_schema() {
  return Schema::object("one axis of the sweep")
      .field("pointer", Schema::string().doc(
                            "RFC 6901 JSON pointer into the base scene, e.g. /fluid/resolution; it "
                            "must address a value the scene has (defaults count)"))
      .field("values", Schema::array(any_value()).min_items(1).doc("the values it takes"))
      .field("small", Schema::array(any_value())
                          .min_items(1)
                          .optional()
                          .doc("the values with --small (the test suite's few points; default: "
                               "\"values\")"))
      .field("spacing", Schema::string("none")
                            .one_of({"none", "value", "inverse"})
                            .doc("for the observed order: 'value' when the value is the step h "
                                 "(a time step), 'inverse' when h ~ 1/value (a resolution)"))
      .field("label", Schema::string().optional().doc(
                          "results.csv column (default: the pointer's last two segments)"));
}

Schema measures_schema() {
  auto variant = Schema::variant("measure", "an error measure of each run's outputs");
  for (const auto& m : error_measures()) {
    Schema options = Schema::from_json(m.params.json());
    options.field("label", Schema::string().optional().doc(
                               "results.csv column (default: the measure's name)"));
    variant.option(m.name, options);
  }
  return Schema::array(variant);
}

/// "/fluid/pressure/tolerance" -> "pressure.tolerance".
std::string default_label(const std::string& pointer) {
  std::vector<std::string> parts;
  std::stringstream s(pointer);
  for (std::string part; std::getline(s, part, '/');)
    if (!part.empty()) parts.push_back(part);
  if (parts.empty()) return "value";
  if (parts.size() == 1) return parts.back();
  return parts[parts.size() - 2] + "." + parts.back();
}

Json read_json(const fs::path& file, const std::string& what) {
  std::ifstream in(file);
  std::error_code ec;
  if (!fs::is_regular_file(file, ec) || !in)
    throw IoError("cannot read " + what + " " + file.string() + ": no such file");
  std::stringstream text;
  text << in.rdbuf();
  try {
    return Json::parse(text.str());
  } catch (const Json::parse_error& e) {
    throw SceneError(file.string(), "", std::string("JSON syntax error: ") + e.what());
  }
}

/// What is wrong with a pointer into the resolved base scene, or "". Every segment but the
/// last must exist (an array index within range); the last may be a key the file and the
/// defaults leave out (an optional setting such as /time/max_dt): whether the scene takes
/// it is for its schema to say (plan_sweep reports an unknown key at the pointer).
std::string pointer_problem(const std::string& pointer, const Json& scene) {
  try {
    Json::json_pointer ptr(pointer);
  } catch (const Json::exception&) {
    return "'" + pointer +
           "' is not a JSON pointer: write it as /key/key/index, e.g. /fluid/resolution";
  }
  if (pointer.empty()) return "the empty pointer addresses the whole scene: name one value";
  std::vector<std::string> parts;
  std::stringstream s(pointer.substr(1));
  for (std::string part; std::getline(s, part, '/');) parts.push_back(part);
  if (!pointer.empty() && pointer.back() == '/') parts.emplace_back();
  const Json* node = &scene;
  std::string walked;
  const auto where = [&] { return walked.empty() ? std::string("/") : walked; };
  for (size_t i = 0; i < parts.size(); ++i) {
    // RFC 6901 escapes.
    std::string part;
    for (size_t c = 0; c < parts[i].size(); ++c)
      if (parts[i][c] == '~' && c + 1 < parts[i].size()) {
        part += parts[i][c + 1] == '1' ? '/' : '~';
        ++c;
      } else {
        part += parts[i][c];
      }
    const bool last = i + 1 == parts.size();
    if (node->is_object()) {
      if (node->contains(part)) {
        node = &(*node)[part];
      } else if (last) {
        return "";
      } else {
        std::vector<std::string> keys;
        for (const auto& [k, _] : node->items()) keys.push_back(k);
        std::string list;
        for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
        return "the base scene has no '" + part + "' at " + where() +
               " (even with the defaults filled in)" + runtime::did_you_mean(part, keys) +
               "; keys there: " + list;
      }
    } else if (node->is_array()) {
      const bool digits =
          !part.empty() && part.find_first_not_of("0123456789") == std::string::npos;
      if (!digits || std::stoull(part) >= node->size())
        return "the base scene has no '" + part + "' at " + where() + ": it is an array of " +
               std::to_string(node->size()) + " (index it by 0.." +
               std::to_string(node->size() - 1) + ")";
      node = &(*node)[std::stoull(part)];
    } else {
      return "the base scene's " + where() + " is " + runtime::describe_value(*node) +
             ", which has no '" + part + "'";
    }
    walked += "/" + parts[i];
  }
  return "";
}

}  // namespace

std::string to_string(Spacing spacing) {
  switch (spacing) {
    case Spacing::Value:
      return "value";
    case Spacing::Inverse:
      return "inverse";
    default:
      return "none";
  }
}

Schema bench_spec_schema() {
  return Schema::object("A shellflow bench: a base scene swept along axes, each run measured.")
      .field("name", Schema::string().optional().doc(
                         "bench name and folder out/bench/<name>/ (default: the file's stem)"))
      .field("description", Schema::string().optional().doc("free text for people"))
      .field("scene", Schema::file().doc("the base scene, relative to this file"))
      .field("frames", Schema::integer().min(1).optional().doc(
                           "frames of each run (default: the scene's /time/frames)"))
      .field("small_frames",
             Schema::integer().min(1).optional().doc("frames of each run with --small"))
      .field("keep_outputs", Schema::boolean(false).doc(
                                 "keep the scene's writers (meshes, VDB, previews); off, a run "
                                 "writes only metrics.csv and run.json and its time is the "
                                 "simulation's"))
      .field("sweep", Schema::array(axis_schema())
                          .default_value(Json::array())
                          .doc("the axes; every combination runs (cartesian product)"))
      .field("measures", measures_schema()
                             .default_value(Json::array())
                             .doc("error measures taken from each completed run"));
}

BenchSpec load_bench_spec(const fs::path& file_in, bool small,
                          const std::vector<fs::path>& plugin_dirs) {
  std::error_code ec;
  const fs::path file = fs::absolute(file_in, ec).lexically_normal();
  Json doc = read_json(file, "bench spec");
  if (!doc.is_object())
    throw runtime::SceneValidationError(
        file.string(),
        {{"", "expected a JSON object at the top level, found " + runtime::describe_value(doc)}});
  runtime::SchemaValidator validator(file.parent_path());
  validator.validate(doc, bench_spec_schema().json(), "");
  if (!validator.issues().empty())
    throw runtime::SceneValidationError(file.string(), validator.issues());

  BenchSpec spec;
  spec.file = file;
  spec.name = doc.contains("name") ? doc["name"].get<std::string>() : file.stem().string();
  if (!runtime::is_plain_name(spec.name))
    validator.add_issue("/name", "the bench name '" + spec.name +
                                     "' becomes the folder out/bench/<name>/: letters, digits, "
                                     "'_', '-' and '.', not starting with '.'");
  spec.description = doc.value("description", "");
  spec.scene_file = doc["scene"].get<std::string>();
  if (doc.contains("frames")) spec.frames = doc["frames"].get<int>();
  if (small && doc.contains("small_frames")) spec.frames = doc["small_frames"].get<int>();
  spec.keep_outputs = doc["keep_outputs"];
  spec.plugin_dirs = plugin_dirs;

  // The base scene must be valid on its own: its own file names its problems.
  const auto scene = runtime::load_scene(spec.scene_file, plugin_dirs);
  spec.base_scene = read_json(spec.scene_file, "scene");
  spec.resolved_scene = scene.resolved;

  std::vector<std::string> labels;
  for (size_t i = 0; i < doc["sweep"].size(); ++i) {
    const Json& a = doc["sweep"][i];
    const std::string path = pointer_append("/sweep", i);
    SweepAxis axis;
    axis.pointer = a["pointer"];
    if (const auto problem = pointer_problem(axis.pointer, spec.resolved_scene); !problem.empty())
      validator.add_issue(pointer_append(path, "pointer"), problem);
    const Json& values = small && a.contains("small") ? a["small"] : a["values"];
    axis.values.assign(values.begin(), values.end());
    axis.values_path = pointer_append(path, small && a.contains("small") ? "small" : "values");
    const std::string spacing = a["spacing"];
    axis.spacing = spacing == "value"     ? Spacing::Value
                   : spacing == "inverse" ? Spacing::Inverse
                                          : Spacing::None;
    if (axis.spacing != Spacing::None)
      for (size_t k = 0; k < values.size(); ++k)
        if (!values[k].is_number() || values[k].get<double>() <= 0.0)
          validator.add_issue(pointer_append(axis.values_path, k),
                              "a refinement axis (\"spacing\": \"" + spacing +
                                  "\") takes positive numbers, found " +
                                  runtime::describe_value(values[k]));
    axis.label = a.contains("label") ? a["label"].get<std::string>() : default_label(axis.pointer);
    for (const auto& other : spec.axes)
      if (other.pointer == axis.pointer)
        validator.add_issue(pointer_append(path, "pointer"),
                            "the pointer " + axis.pointer + " is swept twice: merge the values");
    labels.push_back(axis.label);
    spec.axes.push_back(std::move(axis));
  }

  for (size_t i = 0; i < doc["measures"].size(); ++i) {
    Json params = doc["measures"][i];
    const std::string path = pointer_append("/measures", i);
    MeasureSpec m;
    m.json_path = path;
    m.measure = params["measure"];
    m.label = params.contains("label") ? params["label"].get<std::string>() : m.measure;
    params.erase("measure");
    params.erase("label");
    const ErrorMeasure* definition = find_error_measure(m.measure);
    if (const std::string problem = definition->bind(params, spec.resolved_scene); !problem.empty())
      validator.add_issue(path, problem);
    m.params = params;
    if (definition->against_finest &&
        std::none_of(spec.axes.begin(), spec.axes.end(),
                     [](const SweepAxis& a) { return a.spacing != Spacing::None; }))
      validator.add_issue(path,
                          "'" + m.measure +
                              "' compares each run with the finest one: give one axis a "
                              "\"spacing\" (\"value\" or \"inverse\") to say which is finest");
    if (std::find(labels.begin(), labels.end(), m.label) != labels.end())
      validator.add_issue(
          pointer_append(path, "label"),
          "the column '" + m.label + "' is already used by an axis or a measure: give a \"label\"");
    labels.push_back(m.label);
    spec.measures.push_back(std::move(m));
  }
  if (!validator.issues().empty())
    throw runtime::SceneValidationError(file.string(), validator.issues());
  return spec;
}

}  // namespace shellflow::bench
