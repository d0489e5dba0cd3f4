#pragma once
// Finds plugins by name along the search path and keeps them loaded for the run.
//
// Search order: the scene's "plugin_path" entries, then SHELLFLOW_PLUGIN_PATH
// (colon-separated), then the build tree's plugin folder, then the install prefix's.
// Files named shellflow_*.so in those folders are candidates; a plugin's name is the one
// its descriptor declares. A plugin found in an earlier folder shadows one of the same
// name in a later folder (a user's override); two files declaring the same name in
// one folder, or two different files used by one scene, are an error.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "shellflow/runtime/plugin_library.hpp"

namespace shellflow::runtime {

/// A candidate file seen on the search path, loadable or not.
struct PluginCandidate {
  std::filesystem::path file;
  std::shared_ptr<PluginLibrary> library;  ///< null if it failed to load
  std::string error;                       ///< why it failed
  std::string shadowed_by;                 ///< file of an earlier plugin with the same name
};

class PluginRegistry {
 public:
  explicit PluginRegistry(std::vector<std::filesystem::path> search_dirs);

  /// The default search path after the scene's own entries.
  static std::vector<std::filesystem::path> default_search_dirs();

  /// A plugin by name, or by file path (anything containing '/' or ending in ".so").
  /// @throw PluginError: not found (with the folders searched and a did-you-mean), the file
  ///   is broken or incompatible, two files claim the name, or the kind is wrong.
  std::shared_ptr<PluginLibrary> get(const std::string& name_or_file, PluginKind kind);

  /// Every candidate on the search path, for `shellflow plugins`.
  const std::vector<PluginCandidate>& candidates();
  const std::vector<std::filesystem::path>& search_dirs() const { return m_search_dirs; }

 private:
  void scan();
  std::shared_ptr<PluginLibrary> use(std::shared_ptr<PluginLibrary> library);

  std::vector<std::filesystem::path> m_search_dirs;
  bool m_scanned = false;
  std::vector<PluginCandidate> m_candidates;
  std::map<std::string, std::shared_ptr<PluginLibrary>> m_used;  ///< name -> library in this run
};

}  // namespace shellflow::runtime
