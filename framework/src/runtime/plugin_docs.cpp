#include "shellflow/runtime/plugin_docs.hpp"

#include "shellflow/runtime/schema_validator.hpp"

namespace shellflow::runtime {

namespace {
void append_fields(std::string& out, const sdk::Schema::Json& object, int indent) {
  const std::string pad(indent, ' ');
  for (const auto& [name, field] : object.at("fields").items()) {
    out += pad + name + ": " + describe_schema(field);
    if (field.contains("default"))
      out += ", default " + field["default"].dump();
    else if (field.value("optional", false))
      out += ", optional";
    else if (field.at("kind") != "object")
      out += ", required";
    if (field.contains("doc")) out += " — " + field["doc"].get<std::string>();
    out += "\n";
    out += format_schema_docs(field, indent + 4);
  }
}
}  // namespace

std::string format_schema_docs(const sdk::Schema::Json& schema, int indent) {
  std::string out;
  const std::string kind = schema.at("kind");
  if (kind == "object") {
    append_fields(out, schema, indent);
  } else if (kind == "array") {
    const auto& items = schema.at("items");
    if (items.at("kind") == "object" || items.at("kind") == "variant") {
      out += std::string(indent, ' ') + "each entry: " + describe_schema(items) + "\n";
      out += format_schema_docs(items, indent + 4);
    }
  } else if (kind == "variant") {
    for (const auto& [option, object] : schema.at("options").items()) {
      out += std::string(indent, ' ') + "\"" + schema.at("key").get<std::string>() + "\": \"" +
             option + "\"";
      if (object.contains("doc")) out += " — " + object["doc"].get<std::string>();
      out += "\n";
      append_fields(out, object, indent + 4);
    }
  }
  return out;
}

}  // namespace shellflow::runtime
