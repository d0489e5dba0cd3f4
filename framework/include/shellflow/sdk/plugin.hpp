#pragma once
// What a plugin author includes: the interfaces, the schema builder and the
// registration macros. A new solid is one class plus one line:
//
//   class FallingPlate final : public shellflow::sdk::SolidSolver {
//    public:
//     static shellflow::sdk::Schema schema();
//     FallingPlate(const nlohmann::json& params, const shellflow::sdk::Context& context);
//     ...
//   };
//   SHELLFLOW_SOLID_PLUGIN(FallingPlate, "falling_plate")
//
// The macro writes the extern "C" entry symbol and the descriptor; exceptions thrown
// by the constructor become a ShellflowCreateError (ConfigError keeps its JSON path).

#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>

#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/sdk/plugin_abi.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/solid_solver.hpp"
#include "shellflow/sdk/writer.hpp"

#ifndef SHELLFLOW_PLUGIN_VERSION
#define SHELLFLOW_PLUGIN_VERSION "0.1.0"
#endif

namespace shellflow::sdk {

/// Context <-> JSON, for the trip across the C boundary.
nlohmann::json context_to_json(const Context& context);
Context context_from_json(const nlohmann::json& j);

namespace detail {

inline void fill_create_error(ShellflowCreateError* error, const char* path, const char* message) {
  if (!error) return;
  std::snprintf(error->json_path, sizeof error->json_path, "%s", path);
  std::snprintf(error->message, sizeof error->message, "%s", message);
}

/// create() for class T behind interface Base; catches everything.
template <class T, class Base>
void* create_instance(const char* params_json, const char* context_json,
                      ShellflowCreateError* error) {
  try {
    const auto params = nlohmann::json::parse(params_json);
    const auto context = context_from_json(nlohmann::json::parse(context_json));
    Base* instance = new T(params, context);
    return static_cast<void*>(instance);
  } catch (const ConfigError& e) {
    fill_create_error(error, e.json_path().c_str(), e.what());
  } catch (const std::exception& e) {
    fill_create_error(error, "", e.what());
  } catch (...) {
    fill_create_error(error, "", "unknown exception while creating the plugin");
  }
  return nullptr;
}

template <class Base>
void destroy_instance(void* instance) {
  delete static_cast<Base*>(instance);
}

template <class T>
const char* schema_json() {
  static const std::string text = T::schema().json().dump();
  return text.c_str();
}

}  // namespace detail
}  // namespace shellflow::sdk

/// Low-level form: every descriptor field given. Tests use it to build bad plugins.
#define SHELLFLOW_PLUGIN_DESCRIPTOR(Class, Base, kind_value, name_str, version_str, abi_major_v, \
                                    abi_minor_v, signature_str)                              \
  extern "C" __attribute__((visibility("default"))) const ShellflowPluginDescriptor*         \
  shellflow_plugin_entry() {                                                                 \
    static const ShellflowPluginDescriptor descriptor{                                       \
        abi_major_v,                                                                         \
        abi_minor_v,                                                                         \
        sizeof(ShellflowPluginDescriptor),                                                   \
        signature_str,                                                                       \
        kind_value,                                                                          \
        name_str,                                                                            \
        version_str,                                                                         \
        &::shellflow::sdk::detail::schema_json<Class>,                                       \
        &::shellflow::sdk::detail::create_instance<Class, Base>,                             \
        &::shellflow::sdk::detail::destroy_instance<Base>};                                  \
    return &descriptor;                                                                      \
  }

#define SHELLFLOW_PLUGIN_OF_KIND(Class, Base, kind_value, name_str)                    \
  SHELLFLOW_PLUGIN_DESCRIPTOR(Class, Base, kind_value, name_str, SHELLFLOW_PLUGIN_VERSION, \
                              SHELLFLOW_ABI_MAJOR, SHELLFLOW_ABI_MINOR, SHELLFLOW_BUILD_SIGNATURE)

#define SHELLFLOW_SOLID_PLUGIN(Class, name_str) \
  SHELLFLOW_PLUGIN_OF_KIND(Class, ::shellflow::sdk::SolidSolver, SHELLFLOW_KIND_SOLID, name_str)
#define SHELLFLOW_FLUID_PLUGIN(Class, name_str) \
  SHELLFLOW_PLUGIN_OF_KIND(Class, ::shellflow::sdk::FluidSolver, SHELLFLOW_KIND_FLUID, name_str)
#define SHELLFLOW_WRITER_PLUGIN(Class, name_str) \
  SHELLFLOW_PLUGIN_OF_KIND(Class, ::shellflow::sdk::Writer, SHELLFLOW_KIND_WRITER, name_str)
