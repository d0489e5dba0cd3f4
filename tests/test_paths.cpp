#include "test_paths.hpp"

namespace shellflow::test_paths {

const std::string& source_dir() {
  static const std::string path = SHELLFLOW_SOURCE_DIR;
  return path;
}
const std::string& cli() {
  static const std::string path = SHELLFLOW_CLI;
  return path;
}
const std::string& plugin_dir() {
  static const std::string path = SHELLFLOW_TEST_PLUGIN_DIR;
  return path;
}
const std::string& bad_plugin_dir() {
  static const std::string path = SHELLFLOW_TEST_BAD_PLUGIN_DIR;
  return path;
}

}  // namespace shellflow::test_paths
