#include "shellflow/runtime/scene.hpp"

#include <fstream>
#include <set>
#include <sstream>

#include "shellflow/runtime/schema_validator.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::runtime {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using sdk::Schema;

namespace {

Schema plugin_node(const std::string& kind, const std::string& doc) {
  return Schema::from_json({{"kind", "plugin"}, {"plugin_kind", kind}, {"doc", doc}});
}

/// Line and column of byte offset `pos` in `text` (1-based), for JSON syntax errors.
std::string line_column(const std::string& text, size_t pos) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < pos && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

Schema scene_schema() {
  return Schema::object("A shellflow scene.")
      .field("name", Schema::string().optional().doc("run name; out/<name>/ (default: file stem)"))
      .field("description", Schema::string().optional().doc("free text for people"))
      .field("plugin_path", Schema::array(Schema::string())
                                .optional()
                                .doc("folders searched first for plugins, relative to this file"))
      .field("gravity", Schema::vec3(0.0, -9.81, 0.0).unit("m/s^2").doc("acceleration of gravity"))
      .field(
          "time",
          Schema::object("time stepping")
              .field("fps",
                     Schema::number(24.0).min(0.0, false).unit("1/s").doc("frames per second"))
              .field("frames", Schema::integer(48).min(1).doc("frames to simulate"))
              .field("max_dt", Schema::number()
                                   .min(0.0, false)
                                   .optional()
                                   .unit("s")
                                   .doc("largest time step (default: no cap beyond the solvers')"))
              .field("cfl", Schema::number(0.9)
                                .min(0.0, false)
                                .max(5.0)
                                .doc("fluid CFL number for the step size")))
      .field("coupling", Schema::object("how fluid and solids exchange forces (§6)")
                             .field("scheme", Schema::string("staggered")
                                                  .one_of({"staggered"})
                                                  .doc("'staggered': the paper's §6 loop"))
                             .field("max_speed",
                                    Schema::number(340.0).min(0.0, false).unit("m/s").doc(
                                        "stability guard: a fluid or shell speed above this "
                                        "stops the run, keeping the frames written so far "
                                        "(default: the speed of sound in air, past which "
                                        "an incompressible model means nothing)")))
      .field("fluid", plugin_node("fluid", "the fluid solver").optional())
      .field("solids", Schema::array(plugin_node("solid", "a solid solver"))
                             .default_value(Json::array())
                             .doc("solid solvers"))
      .field("outputs", Schema::array(plugin_node("writer", "an output writer"))
                              .default_value(Json::array())
                              .doc("output writers"));
}

Scene load_scene(const fs::path& file_in, const std::vector<fs::path>& extra_search_dirs) {
  std::error_code ec;
  const fs::path file = fs::absolute(file_in, ec).lexically_normal();
  const std::string f = file.string();
  std::ifstream in(file);
  if (!fs::is_regular_file(file) || !in)
    throw IoError("cannot read scene file " + f + ": " +
                  (fs::exists(file) ? "not a readable file" : "no such file"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  Json doc;
  try {
    doc = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw SceneError(
        f, "",
        "JSON syntax error at " + line_column(text, e.byte > 0 ? e.byte - 1 : 0) + ": " + e.what());
  }
  if (!doc.is_object())
    throw SceneValidationError(
        f, {{"", "expected a JSON object at the top level, found " + describe_value(doc)}});

  // The scene's own plugin folders come first; they must exist.
  std::vector<ValidationIssue> early;
  std::vector<fs::path> search;
  if (doc.contains("plugin_path") && doc["plugin_path"].is_array()) {
    for (size_t i = 0; i < doc["plugin_path"].size(); ++i) {
      const auto& entry = doc["plugin_path"][i];
      if (!entry.is_string()) continue;  // the schema reports it
      fs::path dir = entry.get<std::string>();
      if (dir.is_relative()) dir = file.parent_path() / dir;
      if (!fs::is_directory(dir))
        early.push_back({pointer_append("/plugin_path", i),
                         "folder not found: " + dir.lexically_normal().string()});
      search.push_back(dir.lexically_normal());
    }
  }
  for (const auto& d : extra_search_dirs) search.push_back(d);
  auto registry = std::make_shared<PluginRegistry>(search);

  std::map<std::string, std::shared_ptr<PluginLibrary>> libraries;  // plugin value -> library
  SchemaValidator validator(file.parent_path(),
                            [&](const std::string& name, const std::string& kind,
                                std::string& error) -> const Schema::Json* {
                              const PluginKind k = kind == "fluid"   ? PluginKind::Fluid
                                                   : kind == "solid" ? PluginKind::Solid
                                                                     : PluginKind::Writer;
                              try {
                                auto lib = registry->get(name, k);
                                libraries[name] = lib;
                                return &lib->schema().json();
                              } catch (const PluginError& e) {
                                error = e.what();
                                return nullptr;
                              }
                            });
  for (auto& issue : early) validator.add_issue(issue.json_path, issue.message);
  validator.validate(doc, scene_schema().json(), "");

  Scene scene;
  scene.file = file;
  if (validator.issues().empty()) {
    if (!doc.contains("fluid") && doc["solids"].empty())
      validator.add_issue(
          "", "nothing to simulate: add a \"fluid\" or at least one entry to \"solids\"");
  }
  // Instance names: given or derived from the plugin name; unique within the scene.
  std::set<std::string> names;
  const auto make_spec = [&](Json& entry, const std::string& path) {
    PluginSpec spec;
    spec.json_path = path;
    const std::string plugin = entry["plugin"].get<std::string>();
    spec.library = libraries.at(plugin);
    std::string name =
        entry.contains("name") ? entry["name"].get<std::string>() : spec.library->name();
    if (!entry.contains("name"))
      for (int k = 2; names.count(name); ++k) name = spec.library->name() + "_" + std::to_string(k);
    if (!names.insert(name).second)
      validator.add_issue(
          pointer_append(path, "name"),
          "the name '" + name + "' is already used by another entry; names must be unique");
    if (name.find('/') != std::string::npos)
      validator.add_issue(pointer_append(path, "name"),
                          "a name may not contain '/': found '" + name + "'");
    spec.instance_name = name;
    entry["name"] = name;
    spec.params = entry;
    spec.params.erase("plugin");
    spec.params.erase("name");
    return spec;
  };
  if (validator.issues().empty()) {
    if (doc.contains("fluid")) scene.fluid = make_spec(doc["fluid"], "/fluid");
    for (size_t i = 0; i < doc["solids"].size(); ++i)
      scene.solids.push_back(make_spec(doc["solids"][i], pointer_append("/solids", i)));
    for (size_t i = 0; i < doc["outputs"].size(); ++i)
      scene.outputs.push_back(make_spec(doc["outputs"][i], pointer_append("/outputs", i)));
  }
  if (!validator.issues().empty()) throw SceneValidationError(f, validator.issues());

  scene.name = doc.contains("name") ? doc["name"].get<std::string>() : file.stem().string();
  scene.gravity = sdk::json_vec3(doc, "gravity");
  const Json& time = doc["time"];
  scene.time.fps = time["fps"];
  scene.time.frames = time["frames"];
  if (time.contains("max_dt")) scene.time.max_dt = time["max_dt"].get<double>();
  scene.time.cfl = time["cfl"];
  scene.coupling_scheme = doc["coupling"]["scheme"];
  scene.max_speed = doc["coupling"]["max_speed"];
  scene.resolved = doc;
  return scene;
}

}  // namespace shellflow::runtime
