#pragma once
// Where a test finds the source tree, the `shellflow` harness and the built plugins.
// Only test_paths.cpp is compiled with the build's absolute paths, so that every other test
// object is the same in any clone and ccache reuses it across folders.

#include <string>

namespace shellflow::test_paths {

const std::string& source_dir();      ///< the source tree's root
const std::string& cli();             ///< the `shellflow` executable
const std::string& plugin_dir();      ///< the build tree's plugin folder
const std::string& bad_plugin_dir();  ///< the test doubles' folders (tests/plugins/test_doubles)

}  // namespace shellflow::test_paths
