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

/// Records the first error of a parse without building a document: the position and the
/// offending token, so that a syntax error and a number no double can hold (1e400, which
/// nlohmann::json reports as out_of_range 406 without a position) are both reported with
/// their line and column.
class SyntaxCheck : public nlohmann::json_sax<Json> {
 public:
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t position, const std::string& token,
                   const nlohmann::detail::exception& e) override {
    m_failed = true;
    m_overflow = e.id == 406;
    // The lexer stands just past the token; syntax errors point at its last character
    // (as parse_error::byte does), an overflowing number at its first.
    m_offset = m_overflow ? (position >= token.size() ? position - token.size() : 0)
                          : (position > 0 ? position - 1 : 0);
    m_token = token;
    m_what = e.what();
    return false;
  }

  bool failed() const { return m_failed; }
  /// What to tell the user, with the line and column of the problem in `text`.
  std::string message(const std::string& text) const {
    if (m_overflow)
      return "JSON syntax error at " + line_column(text, m_offset) + ": the number " + m_token +
             " is beyond what a double can hold (magnitude up to about 1.8e308); write a "
             "finite number";
    return "JSON syntax error at " + line_column(text, m_offset) + ": " + m_what;
  }

 private:
  bool m_failed = false;
  bool m_overflow = false;
  size_t m_offset = 0;
  std::string m_token;
  std::string m_what;
};

}  // namespace

bool is_plain_name(const std::string& name) {
  if (name.empty() || name.front() == '.') return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) return false;
  }
  return true;
}

Schema scene_schema() {
  return Schema::object("A shellflow scene.")
      .field("name", Schema::string().optional().doc(
                         "run name and folder out/<name>/: letters, digits, '_', '-' and "
                         "'.', not starting with '.' (default: the file's stem)"))
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
      .field("coupling",
             Schema::object("how fluid and solids exchange forces (§6)")
                 .field("scheme", Schema::string("staggered")
                                      .one_of({"staggered"})
                                      .doc("'staggered': the paper's §6 loop"))
                 .field("max_speed", Schema::number(340.0)
                                         .min(0.0, false)
                                         .unit("m/s")
                                         .doc("stability guard: a fluid or shell speed above this "
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
  // error_code forms throughout: a path the system refuses (a name too long) is an
  // input error like any missing file, not a filesystem_error (an internal error).
  if (!fs::is_regular_file(file, ec) || !in)
    throw IoError("cannot read scene file " + f + ": " +
                  (fs::exists(file, ec)                               ? "not a readable file"
                   : ec && ec != std::errc::no_such_file_or_directory ? ec.message()
                                                                      : "no such file"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_scene(buffer.str(), file, extra_search_dirs);
}

Scene parse_scene(const std::string& text, const fs::path& file_in,
                  const std::vector<fs::path>& extra_search_dirs) {
  std::error_code ec;
  const fs::path file = fs::absolute(file_in, ec).lexically_normal();
  const std::string f = file.string();
  // Syntax first (a scene is small: parsing it twice costs nothing), so that every
  // problem of the text, numbers out of range included, reads the same way.
  SyntaxCheck syntax;
  if (!Json::sax_parse(text, &syntax) || syntax.failed())
    throw SceneError(f, "", syntax.message(text));
  Json doc = Json::parse(text);
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
      if (std::error_code dir_ec; !fs::is_directory(dir, dir_ec))
        early.push_back({pointer_append("/plugin_path", i),
                         "folder not found: " + dir.lexically_normal().string() +
                             (dir_ec && dir_ec != std::errc::no_such_file_or_directory
                                  ? " (" + dir_ec.message() + ")"
                                  : "")});
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
  // The name becomes the run's folder, out/<name>/: a plain file name keeps the run
  // inside out/ ("../../x" would write two folders above it).
  if (doc.contains("name") && doc["name"].is_string()) {
    const std::string name = doc["name"].get<std::string>();
    if (!is_plain_name(name))
      validator.add_issue("/name", "the scene name '" + name +
                                       "' becomes the run's folder out/<name>/, so it must be "
                                       "a plain file name: letters, digits, '_', '-' and '.', "
                                       "not starting with '.'");
  } else if (const std::string stem = file.stem().string();
             !doc.contains("name") && (stem.empty() || stem.front() == '.')) {
    // Without "name" the stem is used; other characters in it are the user's own choice
    // of file name and cannot leave out/, only a leading '.' (".", "..") can.
    validator.add_issue("/name", "the file name '" + file.filename().string() +
                                     "' starts with '.', so its stem cannot name the run's folder: "
                                     "add a \"name\" (letters, digits, '_', '-' and '.')");
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
