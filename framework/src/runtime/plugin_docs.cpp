#include "shellflow/runtime/plugin_docs.hpp"

#include <functional>

#include "shellflow/runtime/schema_validator.hpp"

namespace shellflow::runtime {

namespace {
// One documented line of a schema: a field, an array's entry or a variant's option.
struct DocLine {
  int depth = 0;
  std::string name;  // field name, or the variant's `"key": "option"`; empty for an entry
  std::string what;  // describe_schema() with the default or "required"
  std::string doc;
};
using Emit = std::function<void(const DocLine&)>;

void walk(const sdk::Schema::Json& schema, int depth, const Emit& emit);

void walk_fields(const sdk::Schema::Json& object, int depth, const Emit& emit) {
  for (const auto& [name, field] : object.at("fields").items()) {
    std::string what = describe_schema(field);
    if (field.contains("default"))
      what += ", default " + field["default"].dump();
    else if (field.value("optional", false))
      what += ", optional";
    else if (field.at("kind") != "object")
      what += ", required";
    emit({depth, name, what, field.value("doc", "")});
    walk(field, depth + 1, emit);
  }
}

void walk(const sdk::Schema::Json& schema, int depth, const Emit& emit) {
  const std::string kind = schema.at("kind");
  if (kind == "object") {
    walk_fields(schema, depth, emit);
  } else if (kind == "array") {
    const auto& items = schema.at("items");
    if (items.at("kind") == "object" || items.at("kind") == "variant") {
      emit({depth, "", "each entry: " + describe_schema(items), ""});
      walk(items, depth + 1, emit);
    }
  } else if (kind == "variant") {
    for (const auto& [option, object] : schema.at("options").items()) {
      emit({depth, "\"" + schema.at("key").get<std::string>() + "\": \"" + option + "\"", "",
            object.value("doc", "")});
      walk_fields(object, depth + 1, emit);
    }
  }
}
}  // namespace

std::string format_schema_docs(const sdk::Schema::Json& schema, int indent) {
  std::string out;
  walk(schema, 0, [&](const DocLine& l) {
    out += std::string(indent + 4 * l.depth, ' ') + l.name;
    if (!l.name.empty() && !l.what.empty()) out += ": ";
    out += l.what;
    if (!l.doc.empty()) out += " — " + l.doc;
    out += "\n";
  });
  return out;
}

std::string format_schema_markdown(const sdk::Schema::Json& schema) {
  std::string out;
  walk(schema, 0, [&](const DocLine& l) {
    out += std::string(2 * l.depth, ' ') + "- ";
    if (!l.name.empty()) out += "`" + l.name + "`";
    if (!l.name.empty() && !l.what.empty()) out += ": ";
    out += l.what;
    if (!l.doc.empty()) out += " — " + l.doc;
    out += "\n";
  });
  return out;
}

}  // namespace shellflow::runtime
