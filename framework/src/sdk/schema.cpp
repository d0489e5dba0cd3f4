#include "shellflow/sdk/schema.hpp"

#include "shellflow/sdk/error.hpp"

namespace shellflow::sdk {

namespace {
Schema::Json leaf(const char* kind) { return Schema::Json{{"kind", kind}}; }
}  // namespace

Schema Schema::number() { return Schema(leaf("number")); }
Schema Schema::number(double v) {
  auto j = leaf("number");
  j["default"] = v;
  return Schema(j);
}
Schema Schema::integer() { return Schema(leaf("integer")); }
Schema Schema::integer(long long v) {
  auto j = leaf("integer");
  j["default"] = v;
  return Schema(j);
}
Schema Schema::boolean(bool v) {
  auto j = leaf("boolean");
  j["default"] = v;
  return Schema(j);
}
Schema Schema::string() { return Schema(leaf("string")); }
Schema Schema::string(const std::string& v) {
  auto j = leaf("string");
  j["default"] = v;
  return Schema(j);
}
Schema Schema::vec3() { return Schema(leaf("vec3")); }
Schema Schema::vec3(double x, double y, double z) {
  auto j = leaf("vec3");
  j["default"] = {x, y, z};
  return Schema(j);
}
Schema Schema::file() { return Schema(leaf("file")); }
Schema Schema::number_list() { return Schema(leaf("number_list")); }
Schema Schema::integer_list() { return Schema(leaf("integer_list")); }

Schema Schema::object(const std::string& doc) {
  auto j = leaf("object");
  j["fields"] = Json::object();
  if (!doc.empty()) j["doc"] = doc;
  return Schema(j);
}
Schema Schema::array(const Schema& items) {
  auto j = leaf("array");
  j["items"] = items.json();
  return Schema(j);
}
Schema Schema::variant(const std::string& key, const std::string& doc) {
  auto j = leaf("variant");
  j["key"] = key;
  j["options"] = Json::object();
  if (!doc.empty()) j["doc"] = doc;
  return Schema(j);
}

Schema& Schema::doc(const std::string& text) {
  m_json["doc"] = text;
  return *this;
}
Schema& Schema::unit(const std::string& text) {
  m_json["unit"] = text;
  return *this;
}
Schema& Schema::min(double bound, bool inclusive) {
  m_json["min"] = bound;
  m_json["min_inclusive"] = inclusive;
  return *this;
}
Schema& Schema::max(double bound, bool inclusive) {
  m_json["max"] = bound;
  m_json["max_inclusive"] = inclusive;
  return *this;
}
Schema& Schema::one_of(std::initializer_list<std::string> choices) {
  m_json["choices"] = std::vector<std::string>(choices);
  return *this;
}
Schema& Schema::min_items(int n) {
  m_json["min_items"] = n;
  return *this;
}
Schema& Schema::subfolder() {
  if (kind() != "string") throw Error("Schema::subfolder() called on a " + kind());
  m_json["format"] = "subfolder";
  return *this;
}
Schema& Schema::optional() {
  m_json["optional"] = true;
  return *this;
}
Schema& Schema::default_value(const Json& value) {
  m_json["default"] = value;
  return *this;
}
Schema& Schema::field(const std::string& name, const Schema& schema) {
  if (kind() != "object") throw Error("Schema::field('" + name + "') called on a " + kind());
  m_json["fields"][name] = schema.json();
  return *this;
}
Schema& Schema::option(const std::string& name, const Schema& object_schema) {
  if (kind() != "variant") throw Error("Schema::option('" + name + "') called on a " + kind());
  if (object_schema.kind() != "object")
    throw Error("Schema::option('" + name + "'): each option must be an object schema");
  m_json["options"][name] = object_schema.json();
  return *this;
}

Schema Schema::from_json(Json j) {
  if (!j.is_object() || !j.contains("kind"))
    throw Error("a parameter schema must be a JSON object with a \"kind\"");
  return Schema(std::move(j));
}

}  // namespace shellflow::sdk
