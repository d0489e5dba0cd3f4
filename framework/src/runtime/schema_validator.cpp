#include "shellflow/runtime/schema_validator.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "shellflow/runtime/did_you_mean.hpp"
#include "shellflow/sdk/writer.hpp"

namespace shellflow::runtime {

using Json = nlohmann::json;
using SchemaJson = sdk::Schema::Json;

namespace {

std::string join_issues(const std::string& file, const std::vector<ValidationIssue>& issues) {
  std::string out;
  for (const auto& issue : issues) {
    if (!out.empty()) out += '\n';
    out += file + ": " + (issue.json_path.empty() ? "/" : issue.json_path) + ": " + issue.message;
  }
  return out;
}

std::string format_number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

std::string range_text(const SchemaJson& s) {
  std::string out;
  if (s.contains("min"))
    out += std::string(s.value("min_inclusive", true) ? " >= " : " > ") +
           format_number(s["min"].get<double>());
  if (s.contains("max")) {
    if (!out.empty()) out += " and";
    out += std::string(s.value("max_inclusive", true) ? " <= " : " < ") +
           format_number(s["max"].get<double>());
  }
  return out;
}

/// Every integer parameter is read as an int (frames, resolutions, node indices), so an
/// integer beyond int's range would wrap (4294967297 frames ran as 1): refuse it here.
bool fits_int(const Json& v) {
  if (v.is_number_unsigned())
    return v.get<Json::number_unsigned_t>() <=
           static_cast<Json::number_unsigned_t>(std::numeric_limits<int>::max());
  const auto i = v.get<Json::number_integer_t>();
  return i >= std::numeric_limits<int>::min() && i <= std::numeric_limits<int>::max();
}

const std::string kIntRange = " (integers here are at most 2147483647 in magnitude)";

std::vector<std::string> keys_of(const SchemaJson& object) {
  std::vector<std::string> keys;
  for (const auto& [k, _] : object.items()) keys.push_back(k);
  return keys;
}

std::string quoted_list(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "'" : ", '") + item + "'";
  return out;
}

}  // namespace

SceneValidationError::SceneValidationError(std::string file, std::vector<ValidationIssue> issues)
    : SceneError(file, issues.empty() ? "" : issues.front().json_path,
                 issues.empty() ? "invalid scene" : issues.front().message),
      m_issues(std::move(issues)) {
  m_full = join_issues(this->file(), m_issues);
}

std::string pointer_append(const std::string& path, const std::string& key) {
  std::string escaped;
  for (char c : key) {
    if (c == '~')
      escaped += "~0";
    else if (c == '/')
      escaped += "~1";
    else
      escaped += c;
  }
  return path + "/" + escaped;
}

std::string pointer_append(const std::string& path, size_t index) {
  return path + "/" + std::to_string(index);
}

std::string describe_value(const Json& v) {
  switch (v.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::boolean:
      return v.get<bool>() ? "true" : "false";
    case Json::value_t::string:
      return "the string " + v.dump();
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
      return "the number " + v.dump();
    case Json::value_t::object:
      return "an object";
    case Json::value_t::array:
      return "an array of " + std::to_string(v.size());
    default:
      return "an unsupported value";
  }
}

std::string describe_schema(const SchemaJson& s) {
  const std::string kind = s.at("kind");
  std::string out;
  if (kind == "number")
    out = "a number" + range_text(s);
  else if (kind == "integer")
    out = "an integer" + range_text(s);
  else if (kind == "boolean")
    out = "true or false";
  else if (kind == "string")
    out = s.contains("choices")
              ? "one of " + quoted_list(s["choices"].get<std::vector<std::string>>())
          : s.value("format", "") == "subfolder"
              ? "a sub-folder of the run's output folder (relative, no '..')"
              : "a string";
  else if (kind == "vec3")
    out = "three numbers [x, y, z]";
  else if (kind == "file")
    out = "a file path (relative to the scene file's folder)";
  else if (kind == "number_list")
    out = "an array of numbers";
  else if (kind == "integer_list")
    out = "an array of integers";
  else if (kind == "object")
    out = "an object";
  else if (kind == "any")
    out = "any JSON value";
  else if (kind == "array")
    out = "an array";
  else if (kind == "variant")
    out = "an object with \"" + s["key"].get<std::string>() + "\": one of " +
          quoted_list(keys_of(s["options"]));
  else if (kind == "plugin")
    out = "an object with \"plugin\": a " + s["plugin_kind"].get<std::string>() + " plugin name";
  else
    out = kind;
  if (s.contains("unit")) out += " [" + s["unit"].get<std::string>() + "]";
  return out;
}

SchemaValidator::SchemaValidator(std::filesystem::path base_dir, PluginResolver resolver)
    : m_base_dir(std::move(base_dir)), m_resolver(std::move(resolver)) {}

void SchemaValidator::add_issue(std::string path, std::string message) {
  m_issues.push_back({std::move(path), std::move(message)});
}

void SchemaValidator::validate(Json& v, const SchemaJson& s, const std::string& path) {
  const std::string kind = s.at("kind");
  const auto expected = [&] {
    return "expected " + describe_schema(s) + ", found " + describe_value(v);
  };
  if (kind == "number" || kind == "integer") {
    validate_number(v, s, path, kind == "integer");
  } else if (kind == "boolean") {
    if (!v.is_boolean()) add_issue(path, expected());
  } else if (kind == "string") {
    if (!v.is_string()) return add_issue(path, expected());
    if (s.contains("choices")) {
      const auto choices = s["choices"].get<std::vector<std::string>>();
      const auto& text = v.get_ref<const std::string&>();
      if (std::find(choices.begin(), choices.end(), text) == choices.end())
        add_issue(path, expected() + did_you_mean(text, choices));
    }
    if (s.value("format", "") == "subfolder")
      if (const std::string problem = sdk::subfolder_problem(v.get<std::string>());
          !problem.empty())
        add_issue(path, problem);
  } else if (kind == "vec3") {
    bool ok = v.is_array() && v.size() == 3;
    if (ok)
      for (const auto& x : v) ok = ok && x.is_number();
    if (!ok) add_issue(path, expected());
  } else if (kind == "file") {
    if (!v.is_string() || v.get_ref<const std::string&>().empty())
      return add_issue(path, expected());
    std::filesystem::path p = v.get<std::string>();
    if (p.is_relative()) p = m_base_dir / p;
    p = p.lexically_normal();
    // The error_code form: a path the system refuses (a name too long) is "not found"
    // with the reason, not a filesystem_error escaping as an internal error.
    if (std::error_code ec; !std::filesystem::is_regular_file(p, ec))
      return add_issue(
          path,
          "file not found: " + p.string() +
              (ec && ec != std::errc::no_such_file_or_directory ? " (" + ec.message() + ")" : "") +
              " (from " + v.dump() + "; relative paths start at the scene file's folder " +
              m_base_dir.string() + ")");
    v = p.string();
  } else if (kind == "number_list" || kind == "integer_list") {
    validate_list(v, s, path, kind == "integer_list");
  } else if (kind == "any") {
    // Checked by whoever reads it.
  } else if (kind == "object") {
    validate_object(v, s, path, {});
  } else if (kind == "plugin") {
    validate_plugin(v, s, path);
  } else if (kind == "variant") {
    validate_variant(v, s, path);
  } else if (kind == "array") {
    if (!v.is_array()) return add_issue(path, expected());
    if (s.contains("min_items") && v.size() < s["min_items"].get<size_t>())
      return add_issue(path, "expected at least " + std::to_string(s["min_items"].get<int>()) +
                                 " entries, found " + std::to_string(v.size()));
    for (size_t i = 0; i < v.size(); ++i) validate(v[i], s.at("items"), pointer_append(path, i));
  } else {
    add_issue(path, "the plugin's schema uses an unknown kind '" + kind + "' (a plugin bug)");
  }
}

void SchemaValidator::validate_number(const Json& v, const SchemaJson& s, const std::string& path,
                                      bool integer) {
  const auto fail = [&] {
    add_issue(path, "expected " + describe_schema(s) + ", found " + describe_value(v));
  };
  if (!v.is_number()) return fail();
  if (integer && !v.is_number_integer()) return fail();
  if (integer && !fits_int(v))
    return add_issue(path,
                     "expected " + describe_schema(s) + ", found " + describe_value(v) + kIntRange);
  const double x = v.get<double>();
  if (!std::isfinite(x)) return fail();
  if (s.contains("min")) {
    const double lo = s["min"];
    if (s.value("min_inclusive", true) ? x < lo : x <= lo) return fail();
  }
  if (s.contains("max")) {
    const double hi = s["max"];
    if (s.value("max_inclusive", true) ? x > hi : x >= hi) return fail();
  }
}

void SchemaValidator::validate_list(const Json& v, const SchemaJson& s, const std::string& path,
                                    bool integer) {
  if (!v.is_array())
    return add_issue(path, "expected " + describe_schema(s) + ", found " + describe_value(v));
  if (s.contains("min_items") && v.size() < s["min_items"].get<size_t>())
    return add_issue(path, "expected at least " + std::to_string(s["min_items"].get<int>()) +
                               " entries, found " + std::to_string(v.size()));
  for (size_t i = 0; i < v.size(); ++i) {
    const bool ok = integer ? v[i].is_number_integer() : v[i].is_number();
    if (!ok)
      add_issue(pointer_append(path, i), std::string("expected ") +
                                             (integer ? "an integer" : "a number") + ", found " +
                                             describe_value(v[i]));
    else if (integer && !fits_int(v[i]))
      add_issue(pointer_append(path, i),
                "expected an integer, found " + describe_value(v[i]) + kIntRange);
  }
}

void SchemaValidator::validate_object(Json& v, const SchemaJson& s, const std::string& path,
                                      const std::vector<std::string>& implicit_keys) {
  if (!v.is_object()) return add_issue(path, "expected an object, found " + describe_value(v));
  const SchemaJson& fields = s.at("fields");
  std::vector<std::string> allowed = implicit_keys;
  for (const auto& k : keys_of(fields)) allowed.push_back(k);
  for (auto& [key, value] : v.items()) {
    if (std::find(implicit_keys.begin(), implicit_keys.end(), key) != implicit_keys.end()) continue;
    if (!fields.contains(key))
      add_issue(pointer_append(path, key), "unknown key '" + key + "'" +
                                               did_you_mean(key, allowed) +
                                               "; allowed keys here: " + quoted_list(allowed));
  }
  for (const auto& [name, field] : fields.items()) {
    const std::string field_path = pointer_append(path, name);
    if (v.contains(name)) {
      validate(v[name], field, field_path);
    } else if (field.contains("default")) {
      v[name] = field["default"];
      if (field.at("kind") == "object" || field.at("kind") == "array")
        validate(v[name], field, field_path);
    } else if (field.at("kind") == "object" && !field.value("optional", false)) {
      // An object whose fields all have defaults may be left out entirely.
      v[name] = Json::object();
      const size_t before = m_issues.size();
      validate(v[name], field, field_path);
      if (m_issues.size() > before) {
        m_issues.resize(before);
        add_issue(path,
                  "missing required key '" + name + "': " + describe_schema(field) +
                      (field.contains("doc") ? " (" + field["doc"].get<std::string>() + ")" : ""));
        v.erase(name);
      }
    } else if (!field.value("optional", false)) {
      add_issue(path,
                "missing required key '" + name + "': expected " + describe_schema(field) +
                    (field.contains("doc") ? " (" + field["doc"].get<std::string>() + ")" : ""));
    }
  }
}

void SchemaValidator::validate_variant(Json& v, const SchemaJson& s, const std::string& path) {
  if (!v.is_object())
    return add_issue(path, "expected " + describe_schema(s) + ", found " + describe_value(v));
  const std::string key = s.at("key");
  const SchemaJson& options = s.at("options");
  const auto names = keys_of(options);
  if (!v.contains(key))
    return add_issue(path, "missing required key '" + key + "': one of " + quoted_list(names));
  const Json& tag = v[key];
  if (!tag.is_string() || !options.contains(tag.get<std::string>())) {
    const std::string hint = tag.is_string() ? did_you_mean(tag.get<std::string>(), names) : "";
    return add_issue(pointer_append(path, key), "expected one of " + quoted_list(names) +
                                                    ", found " + describe_value(tag) + hint);
  }
  validate_object(v, options[tag.get<std::string>()], path, {key});
}

void SchemaValidator::validate_plugin(Json& v, const SchemaJson& s, const std::string& path) {
  const std::string kind = s.at("plugin_kind");
  if (!v.is_object())
    return add_issue(path, "expected an object {\"plugin\": <" + kind +
                               " plugin name>, ...its parameters}, found " + describe_value(v));
  if (!v.contains("plugin") || !v["plugin"].is_string())
    return add_issue(v.contains("plugin") ? pointer_append(path, "plugin") : path,
                     "expected \"plugin\": the name of a " + kind +
                         " plugin (see `shellflow plugins`)" +
                         (v.contains("plugin") ? ", found " + describe_value(v["plugin"]) : ""));
  if (v.contains("name") &&
      (!v["name"].is_string() || v["name"].get_ref<const std::string&>().empty()))
    add_issue(pointer_append(path, "name"), "expected a non-empty string naming this " + kind +
                                                ", found " + describe_value(v["name"]));
  std::string error;
  const SchemaJson* schema =
      m_resolver ? m_resolver(v["plugin"].get<std::string>(), kind, error) : nullptr;
  if (!schema)
    return add_issue(pointer_append(path, "plugin"), error.empty() ? "no plugin resolver" : error);
  validate_object(v, *schema, path, {"plugin", "name"});
}

}  // namespace shellflow::runtime
