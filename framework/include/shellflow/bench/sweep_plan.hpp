#pragma once
// The runs of a bench: every combination of the spec's axes (cartesian product, the last
// axis fastest), each a complete scene checked before anything runs.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/bench/bench_spec.hpp"

namespace shellflow::bench {

struct SweepPoint {
  int index = 0;                       ///< 1-based, in run order
  std::string id;                      ///< run_001, ...: its scene file and run folder
  std::vector<nlohmann::json> values;  ///< one per axis
  /// The scene to run: the base scene with the values set (and its writers dropped unless
  /// the spec keeps them), validated, defaults filled in, file paths absolute.
  nlohmann::json scene;
};

/// "/fluid/resolution = 32, /time/cfl = 0.5"
std::string describe_point(const BenchSpec& spec, const SweepPoint& point);

/// Every combination, each scene validated as `shellflow run` would (plugins' schemas
/// included). @throw runtime::SceneValidationError naming the spec file, the sweep's
/// values that make a scene invalid, and the scene's own problems.
std::vector<SweepPoint> plan_sweep(const BenchSpec& spec);

}  // namespace shellflow::bench
