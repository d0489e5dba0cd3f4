#include "shellflow/runtime/plugin_registry.hpp"

#include <dlfcn.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <sstream>

#include "shellflow/runtime/did_you_mean.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

namespace fs = std::filesystem;

namespace {
bool looks_like_file(const std::string& s) {
  return s.find('/') != std::string::npos || (s.size() > 3 && s.ends_with(".so"));
}

std::string canonical_or_same(const fs::path& p) {
  std::error_code ec;
  const auto c = fs::weakly_canonical(p, ec);
  return ec ? p.string() : c.string();
}

/// The folder of the libshellflow.so this code runs in, asked of the dynamic loader; empty
/// when it cannot say. `cmake --install --prefix P` and a moved install tree put the
/// library in P/lib, whatever prefix was configured, so the plugins are found from here.
fs::path libshellflow_dir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&libshellflow_dir), &info) == 0 || !info.dli_fname)
    return {};
  std::error_code ec;
  const auto file = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path{} : file.parent_path();
}

bool is_inside(const fs::path& dir, const fs::path& root) {
  const auto d = canonical_or_same(dir), r = canonical_or_same(root);
  return d == r || d.starts_with(r + "/");
}
}  // namespace

PluginRegistry::PluginRegistry(std::vector<fs::path> search_dirs)
    : m_search_dirs(std::move(search_dirs)) {}

std::vector<fs::path> PluginRegistry::default_search_dirs() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("SHELLFLOW_PLUGIN_PATH")) {
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ':'))
      if (!item.empty()) dirs.emplace_back(item);
  }
  // A libshellflow in the build tree uses the build tree's plugins; an installed one those
  // installed beside it (<prefix>/lib/shellflow/plugins), then the configured prefix's.
  const fs::path lib_dir = libshellflow_dir();
  if (lib_dir.empty() || is_inside(lib_dir, SHELLFLOW_BUILD_TREE)) {
    dirs.emplace_back(SHELLFLOW_BUILD_PLUGIN_DIR);
  } else {
    const fs::path installed = lib_dir / "shellflow" / "plugins";
    dirs.push_back(installed);
  }
  const fs::path configured = SHELLFLOW_INSTALL_PLUGIN_DIR;
  if (std::none_of(dirs.begin(), dirs.end(), [&](const fs::path& d) {
        return canonical_or_same(d) == canonical_or_same(configured);
      }))
    dirs.push_back(configured);
  return dirs;
}

void PluginRegistry::scan() {
  if (m_scanned) return;
  m_scanned = true;
  std::map<std::string, std::string> first_dir_of;  // plugin name -> folder where it was seen
  std::map<std::string, std::string> first_file_of;
  std::set<std::string> scanned;  // canonical folders
  for (const auto& dir : m_search_dirs) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    // A folder met twice (SHELLFLOW_PLUGIN_PATH set to the build tree's plugin folder,
    // which is searched anyway) is scanned once: its plugins are not twins of themselves.
    if (!scanned.insert(canonical_or_same(dir)).second) continue;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const auto name = entry.path().filename().string();
      if (entry.is_regular_file() && name.starts_with("shellflow_") && name.ends_with(".so"))
        files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      PluginCandidate c{file, nullptr, "", ""};
      try {
        c.library = PluginLibrary::open(file);
      } catch (const PluginError& e) {
        c.error = e.what();
      }
      if (c.library) {
        const auto& name = c.library->name();
        auto seen = first_dir_of.find(name);
        if (seen == first_dir_of.end()) {
          first_dir_of[name] = dir.string();
          first_file_of[name] = file.string();
        } else if (seen->second == dir.string()) {
          c.error = "two plugins named '" + name + "' in " + dir.string() + ": " +
                    first_file_of[name] + " and " + file.string() +
                    "; remove one, or rename it (the name is the second argument of its "
                    "SHELLFLOW_*_PLUGIN macro)";
        } else {
          c.shadowed_by = first_file_of[name];
        }
      }
      m_candidates.push_back(std::move(c));
    }
  }
}

const std::vector<PluginCandidate>& PluginRegistry::candidates() {
  scan();
  return m_candidates;
}

std::shared_ptr<PluginLibrary> PluginRegistry::use(std::shared_ptr<PluginLibrary> library) {
  auto [it, inserted] = m_used.emplace(library->name(), library);
  if (!inserted && canonical_or_same(it->second->file()) != canonical_or_same(library->file()))
    throw PluginError("two plugins named '" + library->name() + "' in one scene: " +
                      it->second->file().string() + " and " + library->file().string() +
                      "; use one of them, or rename one (the name is the second argument of its "
                      "SHELLFLOW_*_PLUGIN macro)");
  return it->second;
}

std::shared_ptr<PluginLibrary> PluginRegistry::get(const std::string& name_or_file,
                                                   PluginKind kind) {
  std::shared_ptr<PluginLibrary> library;
  if (looks_like_file(name_or_file)) {
    library = use(PluginLibrary::open(name_or_file));
  } else {
    if (auto it = m_used.find(name_or_file); it != m_used.end()) {
      library = it->second;
    } else {
      scan();
      // A duplicate in one folder is an error even if another copy loaded fine.
      for (const auto& c : m_candidates)
        if (!c.library || c.library->name() != name_or_file)
          continue;
        else if (!c.error.empty())
          throw PluginError(c.error);
      for (const auto& c : m_candidates)
        if (c.library && c.shadowed_by.empty() && c.library->name() == name_or_file) {
          library = use(c.library);
          break;
        }
      if (!library) {
        // A broken file that looks like the requested plugin explains the failure best.
        const std::string expected_file = "shellflow_" + name_or_file + ".so";
        for (const auto& c : m_candidates)
          if (!c.library && c.file.filename() == expected_file) throw PluginError(c.error);
        std::vector<std::string> names;
        for (const auto& c : m_candidates)
          if (c.library && c.library->kind() == kind) names.push_back(c.library->name());
        std::string searched, available;
        for (const auto& d : m_search_dirs) searched += (searched.empty() ? "" : ", ") + d.string();
        for (const auto& n : names) available += (available.empty() ? "" : ", ") + n;
        throw PluginError(
            "no " + to_string(kind) + " plugin named '" + name_or_file + "'" +
            did_you_mean(name_or_file, names) +
            "; available: " + (available.empty() ? "none" : available) + "; searched: " + searched +
            " (add a folder with the scene's \"plugin_path\" or SHELLFLOW_PLUGIN_PATH)");
      }
    }
  }
  if (library->kind() != kind)
    throw PluginError("plugin '" + library->name() + "' (" + library->file().string() + ") is a " +
                      to_string(library->kind()) + " plugin, but a " + to_string(kind) +
                      " plugin is needed here");
  return library;
}

}  // namespace shellflow::runtime
