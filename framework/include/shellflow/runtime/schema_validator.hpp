#pragma once
// Checks a JSON value against an sdk::Schema, fills in defaults and resolves file
// paths, collecting every problem with its JSON path so that a user sees all mistakes
// of a scene at once.

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::runtime {

struct ValidationIssue {
  std::string json_path;  ///< RFC 6901 pointer, "" for the document root
  std::string message;    ///< what was expected, what was found, how to fix it
};

/// Every problem of one scene file; what() lists them one per line.
class SceneValidationError : public SceneError {
 public:
  SceneValidationError(std::string file, std::vector<ValidationIssue> issues);
  const std::vector<ValidationIssue>& issues() const { return m_issues; }
  const char* what() const noexcept override { return m_full.c_str(); }

 private:
  std::vector<ValidationIssue> m_issues;
  std::string m_full;
};

/// JSON pointer segment escaping (RFC 6901: '~' -> "~0", '/' -> "~1").
std::string pointer_append(const std::string& path, const std::string& key);
std::string pointer_append(const std::string& path, size_t index);

/// Describes a JSON value for messages: `"abc"` (a string), `3.5` (a number), `an object`.
std::string describe_value(const nlohmann::json& value);

class SchemaValidator {
 public:
  /// Looks up the parameter schema of plugin `name` that must be of `kind` ("solid",
  /// "fluid", "writer"); on failure returns null and sets `error` to what to tell the user.
  using PluginResolver = std::function<const sdk::Schema::Json*(
      const std::string& name, const std::string& kind, std::string& error)>;

  /// `base_dir` resolves relative "file" values; `resolver` serves "plugin" nodes
  /// (objects {"plugin": name, "name": instance name, ...the plugin's params}).
  explicit SchemaValidator(std::filesystem::path base_dir, PluginResolver resolver = {});

  /// Validates `value` (modified in place: defaults added, files made absolute).
  void validate(nlohmann::json& value, const sdk::Schema::Json& schema, const std::string& path);

  void add_issue(std::string path, std::string message);
  const std::vector<ValidationIssue>& issues() const { return m_issues; }

 private:
  void validate_number(const nlohmann::json& v, const sdk::Schema::Json& s, const std::string& path,
                       bool integer);
  void validate_object(nlohmann::json& v, const sdk::Schema::Json& s, const std::string& path,
                       const std::vector<std::string>& implicit_keys);
  void validate_plugin(nlohmann::json& v, const sdk::Schema::Json& s, const std::string& path);
  void validate_variant(nlohmann::json& v, const sdk::Schema::Json& s, const std::string& path);
  void validate_list(const nlohmann::json& v, const sdk::Schema::Json& s, const std::string& path,
                     bool integer);

  std::filesystem::path m_base_dir;
  PluginResolver m_resolver;
  std::vector<ValidationIssue> m_issues;
};

/// A one-line summary of a schema node for messages and docs: "number >= 0 [kg/m^2]".
std::string describe_schema(const sdk::Schema::Json& schema);

}  // namespace shellflow::runtime
