#pragma once
// Typed errors. User and input mistakes throw a subclass of shellflow::Error whose
// message says what is wrong and how to fix it; no exception crosses the plugin C
// boundary (the registration macro turns them into error strings).

#include <stdexcept>
#include <string>

namespace shellflow {

/// Base of every error shellflow reports to a user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A scene file is malformed or holds a bad value. The message names the file and the
/// JSON path (RFC 6901 pointer, e.g. `/solids/0/stiffness`).
class SceneError : public Error {
 public:
  SceneError(std::string file, std::string json_path, const std::string& what);
  const std::string& file() const { return m_file; }
  const std::string& json_path() const { return m_json_path; }
  /// The message without the "file: path:" prefix.
  const std::string& detail() const { return m_detail; }

 private:
  std::string m_file;
  std::string m_json_path;
  std::string m_detail;
};

/// A plugin could not be found, loaded, or is incompatible; names the file.
class PluginError : public Error {
 public:
  using Error::Error;
};

/// Reading or writing a file failed.
class IoError : public Error {
 public:
  using Error::Error;
};

/// A simulation produced a non-finite or runaway value.
class NumericalError : public Error {
 public:
  using Error::Error;
};

/// A plugin's configuration was rejected by the plugin itself (beyond the schema).
class ConfigError : public Error {
 public:
  /// `json_path` is relative to the plugin's own object (e.g. `/mesh/radius`).
  ConfigError(std::string json_path, const std::string& what);
  const std::string& json_path() const { return m_json_path; }

 private:
  std::string m_json_path;
};

}  // namespace shellflow

/// Internal invariant check: on in debug and sanitizer builds, off in Release.
#ifdef NDEBUG
#define SHELLFLOW_ASSERT(cond) ((void)0)
#else
#include <cstdio>
#include <cstdlib>
#define SHELLFLOW_ASSERT(cond)                                                         \
  ((cond) ? (void)0                                                                    \
          : (std::fprintf(stderr, "%s:%d: internal assertion failed: %s\n", __FILE__, \
                          __LINE__, #cond),                                            \
             std::abort()))
#endif
