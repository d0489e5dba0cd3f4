#pragma once
// Material, solver and collision settings of the mass-spring cloth, with their defaults.
// The plugin schema (mass_spring_cloth.cpp) reads its defaults from these structs, so
// each default lives in one place.

namespace shellflow::cloth {

/// Material constants in physical units, independent of the mesh resolution: spring
/// constants are derived per edge from these and the triangle areas (cloth_model.cpp).
struct ClothMaterial {
  double surface_density = 0.1;     ///< [kg/m^2]; lumped, a third of each triangle per node
  double stretch_stiffness = 2000;  ///< membrane stiffness Y [N/m] (force per width per strain)
  double stretch_damping = 2.0;  ///< membrane viscosity [N s/m] (force per width per strain rate)
  double shear_stiffness = 200;  ///< cross-edge (shear) spring modulus [N/m]
  double shear_damping = 0.2;    ///< [N s/m]
  double bending_stiffness = 1e-5;  ///< bending rigidity k_b [N m]
  double bending_damping = 1e-7;    ///< [N m s]
  double air_damping = 0.0;         ///< drag per area and velocity [kg/(m^2 s)]
};

enum class LinearSolverKind { ConjugateGradient, Cholmod };

struct SolverSettings {
  LinearSolverKind linear_solver = LinearSolverKind::ConjugateGradient;
  double cg_tolerance = 1e-3;  ///< relative residual of the Jacobi-preconditioned CG (paper: 1e-2)
  int cg_max_iterations = 1000;
  int min_substeps = 1;             ///< substeps per advance() at least
  double max_substep = 1.0 / 24.0;  ///< [s]; more substeps when advance() asks for more
  /// Keep the compressive part of the spring Jacobians (exact but indefinite). Off by
  /// default: the (1 - L0/L) term is clamped at zero so CG sees an SPD matrix
  /// (Choi and Ko 2002); tests switch it on to compare with finite differences.
  bool exact_jacobian = false;
  /// Largest structural strain left at the end of a step (strain_limiter.hpp; Provot 1995
  /// used 10%); 0 switches the limiter off.
  double max_strain = 0.1;
  int strain_limit_sweeps = 40;  ///< Gauss–Seidel sweeps of the limiter, at most
};

struct CollisionSettings {
  double thickness = 0.005;  ///< [m] cloth-cloth and cloth-collider proximity distance
  double friction = 0.3;     ///< Coulomb coefficient for collider and self contacts
  bool self_collision = true;
  int ccd_iterations = 6;  ///< impulse passes before impact zones take over (Bridson 2002 §7.4)
};

}  // namespace shellflow::cloth
