#include "new_solid.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <regex>
#include <string_view>

#include "new_solid_templates.hpp"  // generated from plugins/template_solid and app/new_solid/

namespace shellflow::app {

namespace fs = std::filesystem;

namespace {

// C++20 keywords and alternative tokens: the name becomes a namespace.
constexpr std::array<std::string_view, 97> kKeywords = {
    "alignas",       "alignof",     "and",
    "and_eq",        "asm",         "auto",
    "bitand",        "bitor",       "bool",
    "break",         "case",        "catch",
    "char",          "char8_t",     "char16_t",
    "char32_t",      "class",       "compl",
    "concept",       "const",       "consteval",
    "constexpr",     "constinit",   "const_cast",
    "continue",      "co_await",    "co_return",
    "co_yield",      "decltype",    "default",
    "delete",        "do",          "double",
    "dynamic_cast",  "else",        "enum",
    "explicit",      "export",      "extern",
    "false",         "float",       "for",
    "friend",        "goto",        "if",
    "inline",        "int",         "long",
    "mutable",       "namespace",   "new",
    "noexcept",      "not",         "not_eq",
    "nullptr",       "operator",    "or",
    "or_eq",         "private",     "protected",
    "public",        "register",    "reinterpret_cast",
    "requires",      "return",      "short",
    "signed",        "sizeof",      "static",
    "static_assert", "static_cast", "struct",
    "switch",        "template",    "this",
    "thread_local",  "throw",       "true",
    "try",           "typedef",     "typeid",
    "typename",      "union",       "unsigned",
    "using",         "virtual",     "void",
    "volatile",      "wchar_t",     "while",
    "xor",           "xor_eq",      "final",
    "override",      "import",      "module",
    "main"};

// shellflow's own namespaces (shellflow::NAME would clash with them) and names the
// generated code uses unqualified inside shellflow::NAME.
constexpr std::array<std::string_view, 11> kTaken = {"sdk",      "geometry",  "grid", "linear",
                                                     "coupling", "runtime",   "app",  "testing",
                                                     "std",      "shellflow", "eigen"};

std::string replace_all(std::string text, std::string_view from, std::string_view to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

}  // namespace

std::string plugin_name_problem(const std::string& name) {
  static const std::regex kPattern("[a-z][a-z0-9_]*");
  if (name.empty()) return "the name is empty";
  if (name.size() > 64) return "it is longer than 64 characters";
  if (!std::regex_match(name, kPattern))
    return "use lower-case letters, digits and '_', starting with a letter (as my_cloth)";
  if (name.find("__") != std::string::npos || name.back() == '_')
    return "'__' and a trailing '_' make reserved or awkward C++ names; use single inner '_'";
  if (std::find(kKeywords.begin(), kKeywords.end(), name) != kKeywords.end())
    return "it is a C++ keyword, and the plugin's code lives in namespace shellflow::" + name;
  if (std::find(kTaken.begin(), kTaken.end(), name) != kTaken.end())
    return "shellflow::" + name + " is one of shellflow's own namespaces";
  return {};
}

std::string class_name_for(const std::string& name) {
  std::string out;
  bool upper = true;
  for (char c : name) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper && c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
    upper = false;
  }
  return out;
}

std::vector<std::string> write_new_solid(const std::string& name, const fs::path& dir) {
  if (const auto problem = plugin_name_problem(name); !problem.empty())
    throw Error("'" + name + "' cannot name a plugin: " + problem);
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec))
      throw IoError(dir.string() + " exists and is not a folder; choose another DIR");
    if (!fs::is_empty(dir, ec))
      throw IoError(dir.string() +
                    " is not empty; `shellflow new solid` writes only into a new or empty folder "
                    "(choose another DIR, or empty this one)");
  }

  namespace t = new_solid_templates;
  const std::string cls = class_name_for(name);
  // The template's names, in the order that keeps longer matches intact.
  auto from_template = [&](std::string text) {
    text = replace_all(std::move(text), "template_solid", name);
    text = replace_all(std::move(text), "FallingPlate", cls);
    text = replace_all(std::move(text), "falling_plate", name);
    return text;
  };
  auto from_in = [&](std::string text) {
    text = replace_all(std::move(text), "@NAME@", name);
    text = replace_all(std::move(text), "@CLASS@", cls);
    text = replace_all(std::move(text), "@SHELLFLOW_VERSION_MM@", SHELLFLOW_VERSION_MAJOR_MINOR);
    return text;
  };
  const std::vector<std::pair<std::string, std::string>> files = {
      {name + ".hpp", from_template(t::kHeader)},
      {name + ".cpp", from_template(t::kSource)},
      {"CMakeLists.txt", from_in(t::kCMakeLists)},
      {name + "_test.cpp", from_in(t::kTest)},
      {"scenes/" + name + "_drop.json", from_in(t::kScene)},
  };
  fs::create_directories(dir / "scenes", ec);
  if (ec) throw IoError("cannot create " + (dir / "scenes").string() + ": " + ec.message());
  std::vector<std::string> written;
  for (const auto& [file, text] : files) {
    std::ofstream out(dir / file, std::ios::binary);
    out << text;
    if (!out) throw IoError("cannot write " + (dir / file).string());
    written.push_back(file);
  }
  return written;
}

}  // namespace shellflow::app
