// The loader's bad cases: each gives one clear error naming the file and what to do.
// The bad plugins are built on purpose by tests/plugins/test_doubles.

#include "shellflow/runtime/plugin_registry.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "shellflow/sdk/error.hpp"
#include "test_paths.hpp"

namespace shellflow::runtime {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

const fs::path kPlugins = shellflow::test_paths::plugin_dir();
const fs::path kBad = shellflow::test_paths::bad_plugin_dir();

std::string load_error(PluginRegistry& registry, const std::string& what, PluginKind kind) {
  try {
    registry.get(what, kind);
  } catch (const PluginError& e) {
    return e.what();
  }
  return "no error";
}

TEST(PluginRegistry, FindsABuiltPluginByNameWithItsSchema) {
  PluginRegistry registry({kPlugins});
  const auto lib = registry.get("template_solid", PluginKind::Solid);
  EXPECT_EQ(lib->name(), "template_solid");
  EXPECT_EQ(lib->kind(), PluginKind::Solid);
  EXPECT_TRUE(lib->schema().json().at("fields").contains("surface_density"));
  // Asking again gives the same loaded library, not a second copy.
  EXPECT_EQ(registry.get("template_solid", PluginKind::Solid).get(), lib.get());
}

TEST(PluginRegistry, MissingFileIsNamed) {
  PluginRegistry registry({kPlugins});
  const auto file = (kBad / "nowhere" / "shellflow_ghost.so").string();
  EXPECT_THAT(load_error(registry, file, PluginKind::Solid),
              AllOf(HasSubstr("plugin file not found"), HasSubstr(file)));
}

TEST(PluginRegistry, SharedLibraryWithoutEntrySymbolIsNotAPlugin) {
  PluginRegistry registry({kPlugins});
  const auto file = (kBad / "not_a_plugin" / "shellflow_not_a_plugin.so").string();
  EXPECT_THAT(load_error(registry, file, PluginKind::Solid),
              AllOf(HasSubstr(file), HasSubstr("is not a shellflow plugin"),
                    HasSubstr("shellflow_plugin_entry"), HasSubstr("SHELLFLOW_SOLID_PLUGIN")));
}

TEST(PluginRegistry, OtherAbiMajorIsRejectedWithRebuildAdvice) {
  PluginRegistry registry({kBad / "future_abi"});
  EXPECT_THAT(load_error(registry, "future_abi", PluginKind::Solid),
              AllOf(HasSubstr("shellflow_future_abi.so"), HasSubstr("plugin ABI 99."),
                    HasSubstr("rebuild the plugin")));
}

TEST(PluginRegistry, NewerAbiMinorIsRejected) {
  PluginRegistry registry({kBad / "newer_minor"});
  EXPECT_THAT(load_error(registry, "newer_minor", PluginKind::Solid),
              AllOf(HasSubstr("shellflow_newer_minor.so"), HasSubstr("needs plugin ABI " + std::to_string(SHELLFLOW_ABI_MAJOR) + ".99")));
}

TEST(PluginRegistry, OtherBuildSignatureIsRejected) {
  PluginRegistry registry({kBad / "other_compiler"});
  EXPECT_THAT(load_error(registry, "other_compiler", PluginKind::Solid),
              AllOf(HasSubstr("shellflow_other_compiler.so"), HasSubstr("some-other-compiler"),
                    HasSubstr("same compiler")));
}

TEST(PluginRegistry, TwoPluginsOfOneNameInOneFolderAreAnError) {
  PluginRegistry registry({kBad / "twins"});
  EXPECT_THAT(load_error(registry, "twin", PluginKind::Solid),
              AllOf(HasSubstr("two plugins named 'twin'"), HasSubstr("shellflow_twin_a.so"),
                    HasSubstr("shellflow_twin_b.so"), HasSubstr("remove one")));
}

TEST(PluginRegistry, TwoFilesOfOneNameInOneSceneAreAnError) {
  PluginRegistry registry({kPlugins});
  registry.get("template_solid", PluginKind::Solid);
  const auto impostor = (kBad / "shadow" / "shellflow_template_solid.so").string();
  EXPECT_THAT(load_error(registry, impostor, PluginKind::Solid),
              AllOf(HasSubstr("two plugins named 'template_solid' in one scene"), HasSubstr(impostor)));
}

TEST(PluginRegistry, EarlierFolderShadowsLaterOne) {
  PluginRegistry registry({kBad / "shadow", kPlugins});
  const auto lib = registry.get("template_solid", PluginKind::Solid);
  EXPECT_EQ(lib->file(), kBad / "shadow" / "shellflow_template_solid.so");
  bool saw_shadowed = false;
  for (const auto& c : registry.candidates())
    saw_shadowed = saw_shadowed || (c.file.parent_path() == kPlugins && !c.shadowed_by.empty());
  EXPECT_TRUE(saw_shadowed);
}

// SHELLFLOW_PLUGIN_PATH set to the build tree's plugin folder put it on the search path
// twice, and every plugin was "two plugins named 'x' in <dir>: <dir>/x.so and <dir>/x.so".
TEST(PluginRegistry, AFolderListedTwiceIsScannedOnce) {
  PluginRegistry registry({kPlugins, kPlugins / "." / "", kPlugins});
  const auto lib = registry.get("template_solid", PluginKind::Solid);
  EXPECT_EQ(lib->name(), "template_solid");
  size_t copies = 0;
  for (const auto& c : registry.candidates()) {
    EXPECT_EQ(c.error, "") << c.file;
    if (c.library && c.library->name() == "template_solid") ++copies;
  }
  EXPECT_EQ(copies, 1u);
}

TEST(PluginRegistry, UnknownNameSuggestsTheClosestAndListsFolders) {
  PluginRegistry registry({kPlugins});
  EXPECT_THAT(load_error(registry, "template_sold", PluginKind::Solid),
              AllOf(HasSubstr("no solid plugin named 'template_sold'"),
                    HasSubstr("did you mean 'template_solid'"), HasSubstr(kPlugins.string())));
}

TEST(PluginRegistry, WrongKindIsNamed) {
  PluginRegistry registry({kPlugins});
  EXPECT_THAT(load_error(registry, "template_solid", PluginKind::Writer),
              AllOf(HasSubstr("is a solid plugin"), HasSubstr("writer plugin is needed")));
}

}  // namespace
}  // namespace shellflow::runtime
