#pragma once
// The "kinematic_shell" solid: one triangle shell (a generated or OBJ mesh, placed by
// "transform") moved by a script (Motion). It ignores fluid forces (one-way coupled, §5:
// a kinematic object's velocity is simply imposed on the fluid) and sets its state at
// t + dt exactly, whatever dt.

#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "shellflow/kinematic_shell/motion.hpp"
#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/solid_solver.hpp"

namespace shellflow::kinematic_shell {

class KinematicShell final : public sdk::SolidSolver {
 public:
  static sdk::Schema schema();
  /// `params` validated against schema() (defaults filled in). Throws ConfigError for
  /// values the schema cannot check, IoError for an unreadable OBJ file.
  KinematicShell(const nlohmann::json& params, const sdk::Context& context);

  std::span<const sdk::ShellSurface> surfaces() const override { return m_surface; }
  void advance(double t, double dt, std::span<const sdk::TriangleVectors> triangle_forces) override;
  void save(sdk::StateWriter& out) const override;
  void restore(sdk::StateReader& in) override;
  /// "kinetic_energy" [J] with lumped node masses (a third of each triangle's mass); the
  /// mean of the nodes, "center_x", "center_y", "center_z" [m] (a point that moves with a
  /// rigid motion, on a straight line under linear keyframes); and "max_edge_strain", the
  /// largest |L − L0| / L0 of the mesh's edges against the rest mesh (0 for a rigid motion).
  void report(sdk::Metrics& out) const override;

  double time() const { return m_time; }
  /// Node positions at t = 0 after "transform" (before any motion).
  const sdk::Positions& rest_positions() const { return m_rest; }

 private:
  void update();

  sdk::Positions m_rest;
  std::vector<std::array<int, 2>> m_edges;  ///< each edge of the mesh once
  Eigen::VectorXd m_rest_length;            ///< per edge, at rest
  std::unique_ptr<Motion> m_motion;
  std::array<sdk::ShellSurface, 1> m_surface;
  Eigen::VectorXd m_node_mass;
  double m_time = 0.0;
};

}  // namespace shellflow::kinematic_shell
