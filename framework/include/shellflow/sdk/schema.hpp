#pragma once
// Parameter schemas: each plugin declares its parameters (name, type, default, range,
// one-line doc) in one place, a static `schema()` function. The runtime validates a
// scene against it before anything runs, fills in defaults, and `shellflow plugins`
// prints it as documentation.
//
//   static sdk::Schema schema() {
//     return sdk::Schema::object("A rigid plate falling under gravity.")
//         .field("surface_density", sdk::Schema::number(1.0).min(0.0, false).unit("kg/m^2")
//                                       .doc("mass per unit area of the shell"))
//         .field("mesh", sdk::Schema::variant("type", "shape of the shell")
//                            .option("grid", grid_schema())
//                            .option("obj", obj_schema()));
//   }
//
// A field without a default is required; `.optional()` makes it optional without one.

#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace shellflow::sdk {

class Schema {
 public:
  using Json = nlohmann::ordered_json;

  // Leaves. Without a default the value is required.
  static Schema number();
  static Schema number(double default_value);
  static Schema integer();
  static Schema integer(long long default_value);
  static Schema boolean(bool default_value);
  static Schema string();
  static Schema string(const std::string& default_value);
  static Schema vec3();
  static Schema vec3(double x, double y, double z);
  /// A path to an existing file, resolved relative to the scene file's folder.
  static Schema file();
  /// A list of numbers (e.g. times) or integers (e.g. node indices).
  static Schema number_list();
  static Schema integer_list();

  // Containers.
  static Schema object(const std::string& doc = "");
  static Schema array(const Schema& items);
  /// An object whose `key` field ("type") selects one of several object schemas.
  static Schema variant(const std::string& key, const std::string& doc = "");

  // Modifiers.
  Schema& doc(const std::string& text);
  Schema& unit(const std::string& text);
  Schema& min(double bound, bool inclusive = true);
  Schema& max(double bound, bool inclusive = true);
  Schema& one_of(std::initializer_list<std::string> choices);  ///< for strings
  Schema& min_items(int n);                                     ///< for arrays and lists
  /// For strings naming a writer's sub-folder of the run's output folder: the validator
  /// refuses absolute paths and ".." components (sdk::subfolder_problem) at their path.
  Schema& subfolder();
  Schema& optional();
  /// A default for containers and lists (leaves take theirs in the constructor).
  Schema& default_value(const Json& value);
  /// Object fields, in the order they are documented.
  Schema& field(const std::string& name, const Schema& schema);
  /// Variant options (each an object schema; the key field is implicit).
  Schema& option(const std::string& name, const Schema& object_schema);

  const Json& json() const { return m_json; }
  static Schema from_json(Json j);

  /// Is this a variant, object, ... (the "kind" field of the JSON form).
  std::string kind() const { return m_json.at("kind").get<std::string>(); }

 private:
  explicit Schema(Json j) : m_json(std::move(j)) {}
  Json m_json;
};

}  // namespace shellflow::sdk
