#pragma once
// Mass, centre of mass and inertia tensor of a thin shell: the mass lives on the
// triangles (surface density × area), not in a solid volume (§5: the rigid bodies of the
// paper are infinitesimally thin shells).
//
// Exact for the triangle mesh: each flat triangle (a, b, c) of area A contributes
//   ∫ 1 dA     = A
//   ∫ x dA     = A (a + b + c) / 3
//   ∫ x xᵀ dA  = A / 12 (a aᵀ + b bᵀ + c cᵀ + s sᵀ),  s = a + b + c
// (second moments of a triangle, e.g. Eberly, "Polyhedral mass properties", 2002, applied
// to a surface), and the inertia tensor about the centre of mass c is
//   I = tr(S) Id − S,  S = ρ Σ ∫ x xᵀ dA − m c cᵀ.

#include <Eigen/Core>

#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::bullet_rigid {

struct ShellMassProperties {
  double area = 0.0;                                         ///< [m^2]
  double mass = 0.0;                                         ///< [kg]
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();  ///< [m], frame of the positions
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();         ///< about the centre of mass [kg m^2]
  /// Principal moments, ascending, and the principal axes as the columns of a rotation
  /// (det = +1): inertia = principal_axes · diag(principal_moments) · principal_axesᵀ.
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();
  Eigen::Matrix3d principal_axes = Eigen::Matrix3d::Identity();
};

/// Mass properties of a shell with per-triangle surface density [kg/m^2].
/// Throws shellflow::Error for a mesh of zero area or a non-positive total mass.
ShellMassProperties shell_mass_properties(const sdk::Positions& positions,
                                          const sdk::Triangles& triangles,
                                          const Eigen::VectorXd& surface_density);

/// Same, with one surface density for every triangle.
ShellMassProperties shell_mass_properties(const sdk::Positions& positions,
                                          const sdk::Triangles& triangles, double surface_density);

}  // namespace shellflow::bullet_rigid
