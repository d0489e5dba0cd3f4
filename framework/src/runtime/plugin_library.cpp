#include "shellflow/runtime/plugin_library.hpp"

#include <dlfcn.h>

#include <Eigen/Core>
#include <cstring>
#include <nlohmann/json.hpp>

#include "shellflow/sdk/error.hpp"

namespace shellflow::runtime {

namespace {
constexpr const char* kRebuildHint =
    "rebuild the plugin against this shellflow SDK (cmake --build in its build folder), or remove "
    "it "
    "from the plugin search path";
}

std::string to_string(PluginKind kind) {
  switch (kind) {
    case PluginKind::Fluid:
      return "fluid";
    case PluginKind::Solid:
      return "solid";
    case PluginKind::Writer:
      return "writer";
  }
  return "unknown";
}

const char* runtime_build_signature() {
  return SHELLFLOW_BUILD_SIGNATURE;
}

std::shared_ptr<PluginLibrary> PluginLibrary::open(const std::filesystem::path& file) {
  const std::string f = file.string();
  // The error_code form: a name the system refuses (too long) is "not found", not a
  // filesystem_error escaping as an internal error.
  std::error_code ec;
  if (!std::filesystem::exists(file, ec))
    throw PluginError("plugin file not found: " + f +
                      (ec && ec != std::errc::no_such_file_or_directory ? " (" + ec.message() + ")"
                                                                        : std::string()) +
                      " (check the name and the scene's \"plugin_path\" / SHELLFLOW_PLUGIN_PATH)");
  std::shared_ptr<PluginLibrary> lib(new PluginLibrary());
  lib->m_file = file;
  dlerror();
  lib->m_handle = dlopen(f.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib->m_handle)
    throw PluginError(
        "cannot load plugin " + f + ": " + dlerror() +
        " (is it a shared library built for this machine, with its dependencies installed?)");
  dlerror();
  auto entry = reinterpret_cast<ShellflowPluginEntry>(dlsym(lib->m_handle, SHELLFLOW_ENTRY_SYMBOL));
  if (!entry)
    throw PluginError(
        f + " is not a shellflow plugin: it exports no '" SHELLFLOW_ENTRY_SYMBOL
            "' symbol (a plugin registers itself with SHELLFLOW_SOLID_PLUGIN(Class, \"name\") "
            "or its FLUID/WRITER twin, and is built with shellflow_add_plugin())");
  const ShellflowPluginDescriptor* d = entry();
  if (!d) throw PluginError(f + ": its entry symbol returned no descriptor; " + kRebuildHint);
  if (d->abi_major != SHELLFLOW_ABI_MAJOR)
    throw PluginError(f + " was built for plugin ABI " + std::to_string(d->abi_major) + "." +
                      std::to_string(d->abi_minor) + " but this shellflow speaks ABI " +
                      std::to_string(SHELLFLOW_ABI_MAJOR) + "." +
                      std::to_string(SHELLFLOW_ABI_MINOR) + ": " + kRebuildHint);
  if (d->abi_minor > SHELLFLOW_ABI_MINOR)
    throw PluginError(f + " needs plugin ABI " + std::to_string(d->abi_major) + "." +
                      std::to_string(d->abi_minor) + ", newer than this shellflow's " +
                      std::to_string(SHELLFLOW_ABI_MAJOR) + "." +
                      std::to_string(SHELLFLOW_ABI_MINOR) + ": update shellflow or " +
                      kRebuildHint);
  if (d->struct_size < sizeof(ShellflowPluginDescriptor))
    throw PluginError(f + ": descriptor is " + std::to_string(d->struct_size) +
                      " bytes, expected " + std::to_string(sizeof(ShellflowPluginDescriptor)) +
                      ": " + kRebuildHint);
  if (!d->build_signature || std::strcmp(d->build_signature, runtime_build_signature()) != 0)
    throw PluginError(f + " was built as '" +
                      std::string(d->build_signature ? d->build_signature : "?") +
                      "' but this shellflow is '" + runtime_build_signature() +
                      "': C++ objects cross the plugin boundary, so both must come from the same "
                      "compiler, standard library and Eigen; " +
                      kRebuildHint);
  if (d->kind < SHELLFLOW_KIND_FLUID || d->kind > SHELLFLOW_KIND_WRITER)
    throw PluginError(f + ": unknown plugin kind " + std::to_string(d->kind) + "; " + kRebuildHint);
  if (!d->name || !*d->name || !d->create || !d->destroy || !d->param_schema_json)
    throw PluginError(f + ": incomplete descriptor (name, create, destroy or schema missing); " +
                      kRebuildHint);
  lib->m_descriptor = d;
  lib->m_name = d->name;
  lib->m_version = d->version ? d->version : "";
  lib->m_kind = d->kind == SHELLFLOW_KIND_FLUID   ? PluginKind::Fluid
                : d->kind == SHELLFLOW_KIND_SOLID ? PluginKind::Solid
                                                  : PluginKind::Writer;
  try {
    lib->m_schema = sdk::Schema::from_json(sdk::Schema::Json::parse(d->param_schema_json()));
  } catch (const std::exception& e) {
    throw PluginError(f + ": its parameter schema is not valid: " + e.what());
  }
  if (lib->m_schema.kind() != "object")
    throw PluginError(f + ": its parameter schema must be an object schema");
  return lib;
}

PluginLibrary::~PluginLibrary() {
  if (m_handle) dlclose(m_handle);
}

}  // namespace shellflow::runtime
