#pragma once
// `shellflow new solid NAME [DIR]`: writes a ready-to-build out-of-tree solid plugin.

#include <filesystem>
#include <string>
#include <vector>

#include "shellflow/sdk/error.hpp"

namespace shellflow::app {

/// Why NAME cannot name a plugin, or empty when it can: lower-case letters, digits and '_',
/// starting with a letter, no "__", at most 64 characters, not a C++ keyword and not one
/// of shellflow's own namespaces (the plugin's code lives in shellflow::NAME).
std::string plugin_name_problem(const std::string& name);

/// "my_cloth" -> "MyCloth": the class name of the generated solid.
std::string class_name_for(const std::string& name);

/// Writes the plugin NAME into `dir` (created; refused when it holds anything): NAME.hpp and
/// NAME.cpp (the template solid's class, schema and registration line), CMakeLists.txt
/// (find_package(shellflow)), NAME_test.cpp (GoogleTest) and scenes/NAME_drop.json.
/// @throw shellflow::Error for a bad name, shellflow::IoError for a non-empty or unwritable
/// folder; nothing is written then.
/// @return the files written, relative to `dir`.
std::vector<std::string> write_new_solid(const std::string& name, const std::filesystem::path& dir);

}  // namespace shellflow::app
