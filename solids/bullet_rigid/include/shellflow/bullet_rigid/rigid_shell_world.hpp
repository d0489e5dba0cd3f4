#pragma once
// RigidShellWorld: rigid thin shells in a Bullet world (double precision).
//
// Each body's Bullet frame is its principal frame: origin at the shell's centre of mass,
// axes along the principal axes of the shell inertia (ShellMassProperties), so Bullet's
// diagonal local inertia is exact. Contact geometry is the shell's own triangle mesh as a
// btGImpactMeshShape with a small margin (see rigid_shell_world.cpp for why GImpact and
// not a convex decomposition).
//
// Determinism of look-ahead (SolidSolver::save/restore): the Bullet world (broadphase,
// dispatcher with its contact manifolds, solver) is rebuilt at the start of every
// advance(), so what advance() computes depends only on the per-body state that save()
// writes. Contact warm starting therefore carries over between the substeps of one
// advance() but not from one advance() to the next.
//
// Other solids' surfaces (a cloth, another solver's shells) enter through set_colliders()
// as kinematic triangle meshes (btGImpactMeshShape in world coordinates, identity pose):
// the dynamic bodies collide with them, they do not feel the bodies (one-way; the other
// solver sees this solver's shells through its own set_colliders()). Their nodes move
// linearly with the given node velocities over the substeps of an advance() and the
// GImpact box tree is refit each substep; Bullet sees each collider as momentarily at
// rest (a deforming mesh has no single rigid velocity).
//
// Bullet headers stay in the .cpp (pimpl).

#include <Eigen/Core>
#include <memory>
#include <span>
#include <vector>

#include "shellflow/bullet_rigid/fluid_wrench.hpp"
#include "shellflow/bullet_rigid/rigid_shell_spec.hpp"
#include "shellflow/bullet_rigid/shell_mass_properties.hpp"
#include "shellflow/sdk/shell_surface.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::bullet_rigid {

/// Pose and velocity of a body's principal frame.
struct RigidBodyState {
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();    ///< world [m]
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();      ///< principal frame → world
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< [m/s]
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< world [rad/s]
};

class RigidShellWorld {
 public:
  /// Throws shellflow::Error for a body of zero area or a non-positive setting.
  RigidShellWorld(const RigidWorldSettings& settings, std::vector<RigidShellSpec> bodies);
  ~RigidShellWorld();
  RigidShellWorld(const RigidShellWorld&) = delete;
  RigidShellWorld& operator=(const RigidShellWorld&) = delete;

  int body_count() const;
  const RigidShellSpec& spec(int body) const;
  /// Mass properties in the world frame of t = 0 (inertia about the centre of mass).
  const ShellMassProperties& mass_properties(int body) const;
  RigidBodyState state(int body) const;
  /// Inertia tensor about the centre of mass in the current world frame [kg m^2].
  Eigen::Matrix3d world_inertia(int body) const;
  /// Its inverse [1/(kg m^2)], from the principal moments (a zero moment: a zero inverse).
  Eigen::Matrix3d world_inverse_inertia(int body) const;
  /// The gravity advance() adds [m/s^2].
  const Eigen::Vector3d& gravity() const;

  /// Node positions R p + c and velocities v + ω × (x − c) of a body's mesh, now.
  void node_positions(int body, sdk::Positions& out) const;
  void node_velocities(int body, sdk::Positions& out) const;

  /// Other solids' surfaces at the start of the next advance() (the SolidSolver's
  /// set_colliders()); an empty set removes them. Meshes are rebuilt only when the set of
  /// triangle arrays changes; positions and velocities are taken every call.
  void set_colliders(sdk::ShellSet colliders);
  int collider_count() const;

  /// Advances from t to t + dt in ceil(dt / max_substep) equal Bullet steps. `wrenches`
  /// holds one external wrench per body (about its centre of mass, held constant over the
  /// step, ignored for kinematic bodies) or is empty. Gravity is added here.
  void advance(double t, double dt, std::span<const Wrench> wrenches);

  int last_substeps() const;
  /// Contact points in Bullet's manifolds at the end of the last advance().
  int contact_count() const;
  /// Σ ½ m |v|² + ½ ωᵀ I ω over the dynamic bodies [J].
  double kinetic_energy() const;
  /// Σ −m g · c over the dynamic bodies [J] (zero at the world origin).
  double potential_energy() const;

  void save(sdk::StateWriter& out) const;
  void restore(sdk::StateReader& in);

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace shellflow::bullet_rigid
