// libFuzzer target over the scene loader and validator (issue 15, item 6): JSON text in,
// shellflow::Error out. It runs what `shellflow validate` runs before constructing any
// plugin: the syntax check, the runtime's scene schema, and each plugin entry against
// that plugin's own parameter schema (the plugins are loaded from the build tree). It does
// not construct plugins: a fuzzed grid or cloth resolution would make one input take
// seconds and gigabytes, which hides real findings behind timeouts and out-of-memory.
//
// A finding is: a sanitizer report, an exception that is not a shellflow::Error (the CLI
// would call it an internal error, exit 2), or a scene that loads but breaks an invariant
// the run relies on, or whose resolved form (run.json's echo) does not load back to
// itself (checked below). Built and run by scripts/fuzz.sh.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "shellflow/runtime/plugin_registry.hpp"
#include "shellflow/runtime/scene.hpp"
#include "shellflow/sdk/error.hpp"

namespace rt = shellflow::runtime;

namespace {

// Relative "file" values resolve against configs/, as for the seed scenes.
const char* const kSceneFile = SHELLFLOW_SOURCE_DIR "/configs/fuzz_input.json";

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "scene_fuzzer: %s\n", what.c_str());
  std::abort();
}

void check_invariants(const rt::Scene& scene) {
  if (!rt::is_plain_name(scene.name)) fail("loaded a scene whose name is not plain: " + scene.name);
  if (!(std::isfinite(scene.time.fps) && scene.time.fps > 0)) fail("fps not finite and positive");
  if (scene.time.frames < 1) fail("frames < 1: " + std::to_string(scene.time.frames));
  if (!(scene.time.cfl > 0 && scene.time.cfl <= 5)) fail("cfl outside (0, 5]");
  if (scene.time.max_dt && !(std::isfinite(*scene.time.max_dt) && *scene.time.max_dt > 0))
    fail("max_dt not finite and positive");
  if (!(std::isfinite(scene.max_speed) && scene.max_speed > 0)) fail("max_speed");
  if (!scene.gravity.allFinite()) fail("gravity not finite");
  if (!scene.fluid && scene.solids.empty()) fail("loaded a scene with nothing to simulate");
}

/// The resolved scene (defaults filled, files absolute) is echoed into run.json; loaded
/// again it must be valid and resolve to itself.
void check_round_trip(const rt::Scene& scene) {
  const std::string echo = scene.resolved.dump();
  try {
    const rt::Scene again = rt::parse_scene(echo, kSceneFile);
    if (again.resolved != scene.resolved) fail("the resolved scene resolves differently:\n" + echo);
  } catch (const shellflow::Error& e) {
    fail(std::string("the resolved scene does not load: ") + e.what() + "\n" + echo);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Keep every plugin loaded for the whole run: each load_scene opens its own registry,
  // and without this the last reference would dlclose a plugin after every input.
  static auto registry = std::make_unique<rt::PluginRegistry>(rt::PluginRegistry::default_search_dirs());
  static std::vector<std::shared_ptr<rt::PluginLibrary>> keep;
  for (const auto& c : registry->candidates())
    if (c.library) keep.push_back(c.library);
  if (keep.empty()) fail("no plugin found on the default search path; build the plugins first");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const rt::Scene scene = rt::parse_scene(text, kSceneFile);
    check_invariants(scene);
    check_round_trip(scene);
  } catch (const shellflow::Error&) {
    // The expected outcome for most inputs: an error naming the file and the JSON path.
  } catch (const std::exception& e) {
    fail(std::string("an exception that is not a shellflow::Error: ") + e.what());
  }
  return 0;
}
