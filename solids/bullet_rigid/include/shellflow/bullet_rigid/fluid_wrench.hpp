#pragma once
// Per-triangle fluid forces (§5.1: pressure jump × area along the normal) summed into one
// force and one torque about the centre of mass of a rigid shell, each force applied at
// its triangle's barycentre.

#include <Eigen/Core>

#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::bullet_rigid {

struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< about the centre of mass [N m]
};

/// F = Σ f_t,  τ = Σ (b_t − c) × f_t with b_t the barycentre of triangle t.
/// `forces` has one row per triangle; an empty matrix gives a zero wrench.
/// Throws shellflow::Error when the row count differs from the triangle count.
Wrench sum_triangle_forces(const sdk::Positions& positions, const sdk::Triangles& triangles,
                           const sdk::TriangleVectors& forces,
                           const Eigen::Vector3d& centre_of_mass);

}  // namespace shellflow::bullet_rigid
