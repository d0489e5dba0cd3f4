#pragma once
// BulletRigidSolver: the "bullet_rigid" solid plugin. Any number of rigid thin shells
// (dynamic or kinematic) and an optional ground plane, stepped by Bullet (§5: the solid is
// a black box; the fluid sees each body's triangle mesh as one ShellSurface).
//
//   {"plugin": "bullet_rigid", "name": "shells",
//    "ground": {"height": 0, "friction": 1, "restitution": 1},
//    "bodies": [{"name": "cup", "mesh": {"type": "open_box", ...},
//                "transform": {"translate": [0, 1, 0]}, "surface_density": 1,
//                "motion": "dynamic", "velocity": [0,0,0], "angular_velocity": [0,0,0],
//                "friction": 0.9, "restitution": 0.2}]}
//
// Fluid forces arrive per triangle and are summed into a force and a torque about each
// dynamic body's centre of mass (§5.1); gravity is the scene's.

#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <vector>

#include "shellflow/bullet_rigid/rigid_shell_spec.hpp"
#include "shellflow/bullet_rigid/rigid_shell_world.hpp"
#include "shellflow/sdk/context.hpp"
#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/solid_solver.hpp"

namespace shellflow::bullet_rigid {

class BulletRigidSolver final : public sdk::SolidSolver {
 public:
  static sdk::Schema schema();

  /// `params` validated against schema() with defaults filled in. Throws ConfigError for
  /// duplicate or malformed body names and a zero ground normal.
  BulletRigidSolver(const nlohmann::json& params, const sdk::Context& context);
  ~BulletRigidSolver() override;

  std::span<const sdk::ShellSurface> surfaces() const override;
  /// Other solids' surfaces: kinematic meshes the dynamic shells collide with.
  void set_colliders(sdk::ShellSet colliders) override;
  void advance(double t, double dt, std::span<const sdk::TriangleVectors> triangle_forces) override;
  void save(sdk::StateWriter& out) const override;
  void restore(sdk::StateReader& in) override;
  /// kinetic_energy [J], potential_energy [J], contacts, substeps.
  void report(sdk::Metrics& out) const override;

  const RigidShellWorld& world() const { return *m_world; }

 private:
  void update_surfaces();

  std::unique_ptr<RigidShellWorld> m_world;
  std::vector<sdk::ShellSurface> m_surfaces;
};

/// The settings and bodies a validated parameter object describes (used by the
/// constructor; tests call it to build worlds from scene-file JSON).
RigidWorldSettings settings_from_json(const nlohmann::json& params, const sdk::Context& context);
std::vector<RigidShellSpec> bodies_from_json(const nlohmann::json& params);

}  // namespace shellflow::bullet_rigid
