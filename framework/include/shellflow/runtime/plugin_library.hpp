#pragma once
// One loaded plugin file: the dlopen handle, its checked descriptor and its schema.

#include <filesystem>
#include <memory>
#include <string>

#include "shellflow/sdk/plugin_abi.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::runtime {

enum class PluginKind { Fluid, Solid, Writer };

std::string to_string(PluginKind kind);  ///< "fluid", "solid", "writer"

class PluginLibrary {
 public:
  /// Opens `file` and checks its descriptor against this runtime's ABI.
  /// @throw PluginError naming the file, the reason and what to do.
  static std::shared_ptr<PluginLibrary> open(const std::filesystem::path& file);
  ~PluginLibrary();
  PluginLibrary(const PluginLibrary&) = delete;
  PluginLibrary& operator=(const PluginLibrary&) = delete;

  const std::filesystem::path& file() const { return m_file; }
  const std::string& name() const { return m_name; }
  const std::string& version() const { return m_version; }
  PluginKind kind() const { return m_kind; }
  const sdk::Schema& schema() const { return m_schema; }
  const ShellflowPluginDescriptor& descriptor() const { return *m_descriptor; }

 private:
  PluginLibrary() = default;
  std::filesystem::path m_file;
  void* m_handle = nullptr;
  const ShellflowPluginDescriptor* m_descriptor = nullptr;
  std::string m_name;
  std::string m_version;
  PluginKind m_kind = PluginKind::Solid;
  sdk::Schema m_schema = sdk::Schema::object();
};

/// This runtime's build signature (what plugins must match).
const char* runtime_build_signature();

}  // namespace shellflow::runtime
