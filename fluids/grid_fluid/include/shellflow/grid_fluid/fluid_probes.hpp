#pragma once
// Probes: figures of a region or a line of the fluid written to metrics.csv each step, so
// that a known answer can be checked from the run's outputs alone (`shellflow bench`):
//   "box"           <name>.smoke_mass (Σ density Δx³ over the nodes inside, smoke) or
//                   <name>.water_volume (Σ H(−φ) Δx³ as LevelSet::volume, water)
//   "water_extent"  <name>.extent: the distance from "from" along the segment to "to" of
//                   the last point with φ <= 0 (φ trilinear, sampled every Δx/4, the zero
//                   crossing interpolated linearly), 0 when the segment is dry. Along the
//                   floor it is a dam break's front; up a vertical line, the surface height.
//   "velocity_error" <name>.max_error = max over faces |u_f − w_f| / max over faces |w_f| and
//                   <name>.rms_error = √(Σ (u_f − w_f)² / Σ w_f²): the face velocities
//                   against an analytic field w ("reference", analytic_velocity.hpp) sampled
//                   at the same faces. After the first step of a field made of w plus a
//                   gradient, it is the projection's error (a manufactured solution).

#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/mac/analytic_velocity.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/sdk/metrics.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

class LevelSet;
class VolumeFraction;

class FluidProbes {
 public:
  static sdk::Schema schema();
  FluidProbes() = default;
  /// `probes`: validated against schema(). @throw ConfigError for a duplicate name, or a box
  /// or segment that never meets `grid`'s domain (`path`: the probes' JSON path, for messages).
  /// `grid`: where a velocity_error probe samples its reference field.
  FluidProbes(const nlohmann::json& probes, const std::string& path, const grid::UniformGrid& grid);

  /// `density`: the smoke's node density (empty for water); `level_set`: null for smoke;
  /// `fraction`: the water's F (null or not enabled: a box reads the level set's volume).
  void report(sdk::Metrics& out, const MacGrid& mac, const std::vector<double>& density,
              const LevelSet* level_set, const VolumeFraction* fraction = nullptr) const;

  bool empty() const { return m_probes.empty(); }

 private:
  enum class Type { Box, WaterExtent, VelocityError };
  struct Probe {
    std::string name;
    Type type = Type::Box;
    Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< box min, or the segment's start
    Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< box max, or the segment's end
    /// velocity_error: the reference sampled at the faces, one array per face family
    std::array<std::vector<double>, 3> reference;
  };
  std::vector<Probe> m_probes;
};

}  // namespace shellflow::grid_fluid
