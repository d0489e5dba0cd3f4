#pragma once
// How a kinematic shell moves: a map from (time, placed rest position) to world position
// and velocity. The scene form is the "motion" variant of the kinematic_shell plugin.

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::kinematic_shell {

class Motion {
 public:
  virtual ~Motion() = default;

  /// Positions and exact velocities at time `t` [s] of the nodes whose positions after the
  /// initial placement ("transform") are `rest` (one node per row). Outputs are resized.
  virtual void evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                        sdk::Positions& velocities) const = 0;
};

/// The shell stays where "transform" put it.
class StaticMotion final : public Motion {
 public:
  void evaluate(double t, const sdk::Positions& rest, sdk::Positions& positions,
                sdk::Positions& velocities) const override;
};

/// The "motion" variant: "static" | "keyframes" | "analytic" | "wave".
sdk::Schema motion_schema();

/// Builds the motion of a validated "motion" object (null: static). Throws ConfigError at
/// `json_path` + "/..." for values the schema cannot check (key times not increasing,
/// zero rotation axis, zero wave direction).
std::unique_ptr<Motion> make_motion(const nlohmann::json& spec,
                                    const std::string& json_path = "/motion");

}  // namespace shellflow::kinematic_shell
