#pragma once
// The plugin ABI: the C structure a plugin's single entry symbol returns. Only C types
// cross this boundary by value; solver objects cross as pointers to the SDK's abstract
// classes, created and destroyed inside the plugin. Configuration crosses as JSON text.
//
// Compatibility rules the loader applies:
//  - abi_major must equal SHELLFLOW_ABI_MAJOR (layout or meaning changed);
//  - abi_minor must be <= SHELLFLOW_ABI_MINOR (fields were appended);
//  - struct_size must be at least the size of the fields of that minor version;
//  - build_signature must equal the runtime's: C++ classes (vtables, std::string,
//    Eigen matrices) cross the boundary, so compiler, standard library, SDK and Eigen
//    versions, and whether AddressSanitizer is on, must agree.

#include <cstddef>
#include <cstdint>

// 6: FluidSolver::domain (vtable); 5: FluidSolver::start (vtable); 4: MultigridPreconditioner::Level (layout); 3: StateWriter
// (layout).
#define SHELLFLOW_ABI_MAJOR 6
#define SHELLFLOW_ABI_MINOR 0
#define SHELLFLOW_ENTRY_SYMBOL "shellflow_plugin_entry"

#define SHELLFLOW_STRINGIFY_IMPL(x) #x
#define SHELLFLOW_STRINGIFY(x) SHELLFLOW_STRINGIFY_IMPL(x)

/// Compiler, standard library, SDK ABI, Eigen version and AddressSanitizer, as one string.
#define SHELLFLOW_BUILD_SIGNATURE                                                      \
  "abi " SHELLFLOW_STRINGIFY(SHELLFLOW_ABI_MAJOR) "." SHELLFLOW_STRINGIFY(             \
      SHELLFLOW_ABI_MINOR) "; " SHELLFLOW_COMPILER_ID "; libstdc++ " SHELLFLOW_STRINGIFY( \
      __GLIBCXX__) "; eigen " SHELLFLOW_STRINGIFY(EIGEN_WORLD_VERSION) "." SHELLFLOW_STRINGIFY(EIGEN_MAJOR_VERSION) "." SHELLFLOW_STRINGIFY(EIGEN_MINOR_VERSION) "; cxx " SHELLFLOW_STRINGIFY(__cplusplus) SHELLFLOW_SANITIZER_ID

// AddressSanitizer is part of the signature: under it Eigen allocates a matrix with its own
// aligned malloc rather than malloc, so a matrix made on one side and freed on the other
// would be a bad free. A plugin for a Sanitize build is built with the same flags (the
// installed shellflow::sdk target passes them on).
#if defined(__SANITIZE_ADDRESS__)
#define SHELLFLOW_SANITIZER_ID "; asan"
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SHELLFLOW_SANITIZER_ID "; asan"
#endif
#endif
#ifndef SHELLFLOW_SANITIZER_ID
#define SHELLFLOW_SANITIZER_ID ""
#endif

#if defined(__clang__)
#define SHELLFLOW_COMPILER_ID "clang " __clang_version__
#elif defined(__GNUC__)
#define SHELLFLOW_COMPILER_ID \
  "gcc " SHELLFLOW_STRINGIFY(__GNUC__) "." SHELLFLOW_STRINGIFY(__GNUC_MINOR__)
#else
#define SHELLFLOW_COMPILER_ID "unknown compiler"
#endif

extern "C" {

enum ShellflowPluginKind : std::uint32_t {
  SHELLFLOW_KIND_FLUID = 1,
  SHELLFLOW_KIND_SOLID = 2,
  SHELLFLOW_KIND_WRITER = 3,
};

/// Filled by create() when it fails: a JSON path inside the plugin's own parameters
/// (may be empty) and a message saying what to change.
struct ShellflowCreateError {
  char json_path[256];
  char message[2048];
};

struct ShellflowPluginDescriptor {
  std::uint32_t abi_major;
  std::uint32_t abi_minor;
  std::uint32_t struct_size;        ///< sizeof(ShellflowPluginDescriptor) in the plugin
  const char* build_signature;      ///< SHELLFLOW_BUILD_SIGNATURE of the plugin's build
  std::uint32_t kind;               ///< ShellflowPluginKind
  const char* name;                 ///< must match the file name shellflow_<name>.so
  const char* version;              ///< the plugin's own version
  const char* (*param_schema_json)();  ///< sdk::Schema as JSON text
  /// Creates an instance from validated params (defaults filled in) and the scene
  /// context, both JSON. Returns the SDK object (SolidSolver*, FluidSolver* or Writer*
  /// as void*) or null with `error` filled. Never throws.
  void* (*create)(const char* params_json, const char* context_json, ShellflowCreateError* error);
  void (*destroy)(void* instance);
};

/// The one symbol a plugin exports.
typedef const ShellflowPluginDescriptor* (*ShellflowPluginEntry)();

}  // extern "C"
