#include "shellflow/sdk/error.hpp"

namespace shellflow {

namespace {
std::string located(const std::string& file, const std::string& path, const std::string& what) {
  std::string where = file.empty() ? std::string("scene") : file;
  if (!path.empty()) where += ": " + path;
  return where + ": " + what;
}
}  // namespace

SceneError::SceneError(std::string file, std::string json_path, const std::string& what)
    : Error(located(file, json_path, what)),
      m_file(std::move(file)),
      m_json_path(std::move(json_path)),
      m_detail(what) {}

ConfigError::ConfigError(std::string json_path, const std::string& what)
    : Error(what), m_json_path(std::move(json_path)) {}

}  // namespace shellflow
