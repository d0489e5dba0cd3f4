#pragma once
// What the rigid-shell world is built from: one RigidShellSpec per body, the ground plane
// and the stepping settings. Plain data, filled from the scene by BulletRigidSolver or
// directly by tests.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "shellflow/geometry/mesh_generators.hpp"

namespace shellflow::bullet_rigid {

enum class Motion {
  Dynamic,    ///< moved by gravity, contacts and fluid forces (two-way coupled, §5.1)
  Kinematic,  ///< moved at a given constant linear and angular velocity (one-way coupled)
};

struct RigidShellSpec {
  std::string name;              ///< unique within the solver
  geometry::SurfaceMesh mesh;    ///< world positions at t = 0
  double surface_density = 1.0;  ///< [kg/m^2]
  Motion motion = Motion::Dynamic;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< of the centre of mass [m/s]
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< [rad/s]
  double friction = 0.9;     ///< Coulomb coefficient (Bullet multiplies the pair's)
  double restitution = 0.2;  ///< (Bullet multiplies the pair's)
};

/// The plane {x : normal · x = height} bounding the world from below.
struct GroundPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  ///< unit, pointing into the world
  double height = 0.0;                                ///< [m]
  double friction = 1.0;     ///< 1 lets each body's own coefficient apply (product rule)
  double restitution = 1.0;  ///< 1 lets each body's own coefficient apply (product rule)
};

struct RigidWorldSettings {
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};  ///< [m/s^2]
  double max_substep = 1.0 / 240.0;  ///< advance(dt) takes ceil(dt / max_substep) equal steps [s]
  double margin = 0.005;             ///< collision skin of every shell (GImpact margin) [m]
  int solver_iterations = 10;        ///< sequential-impulse iterations per substep
  std::optional<GroundPlane> ground;
};

}  // namespace shellflow::bullet_rigid
