#pragma once
// AnalyticVelocity: a velocity field with a closed form, for answers known exactly: the
// fluid's "initial_velocity", the "prescribed_velocity" that carries water in the
// transport tests of the level set literature, and the reference of a "velocity_error"
// probe (fluid_probes).
//
// "taylor_green": the Taylor–Green vortex (Taylor and Green 1937) fitted to the grid's box
// [lo, hi], with x̂ = (x − lo_x) / L_x (and ŷ, ẑ alike) and amplitude U:
//   u = U sin(πx̂) cos(πŷ) cos(πẑ),  v = −U (L_y / L_x) cos(πx̂) sin(πŷ) cos(πẑ),  w = 0.
// It is divergence-free and has no normal velocity on the box's walls (free-slip). Its
// kinetic energy is ρ U² L_x L_y L_z (1 + L_y²/L_x²) / 16, ρ U² L³ / 8 in a cube of side L;
// sampled on the MAC faces of a cube it is discretely divergence-free as well, and its
// discrete energy ½ρ Σ u² Δx³ is the same number (the face sums of sin² and cos² are
// exact half-sums).
//
// With "gradient" G ≠ 0 the field gains the gradient of
//   φ = G L_x / (2π) cos(2πx̂) cos(πŷ) cos(πẑ),
// whose normal derivative is zero on the walls too. The Helmholtz split of the sum into a
// divergence-free field without flow through the walls and a gradient is then exactly
// (Taylor–Green, ∇φ), so one projection (§4.3, Chorin 1968) must return the Taylor–Green
// part: a manufactured solution whose error is the projection's alone. Why 2π along x: with
// one frequency on every axis (cos πx̂ cos πŷ cos πẑ) φ is an eigenfunction of the MAC
// grid's Laplacian whose sampled gradient is exactly a discrete gradient, so its projection
// would be exact at every Δx and show no order of convergence.
//
// "rigid_rotation": u = ω × (x − c), ω = (2π / period) â: a rigid turn about the axis â
// through c, once per period (Zalesak's slotted disk and sphere; Enright et al. 2002, §5.3).
//
// "deformation": LeVeque's (1996) three-dimensional deformation field on the box mapped
// to the unit cube, u_a = L_a û_a(x̂) cos(πt/T) with
//   û = 2 sin²(πx̂) sin(2πŷ) sin(2πẑ),  v̂ = −sin(2πx̂) sin²(πŷ) sin(2πẑ),
//   ŵ = −sin(2πx̂) sin(2πŷ) sin²(πẑ).
// It is divergence-free (each scaled term's divergence is its unit-cube one), has no
// normal velocity on the box's walls, and reverses at t = T/2, so at t = T every point is
// back where it started: the water's shape at T is its shape at 0 (Enright et al. 2002,
// §5.4, with T = 3).

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

class MacGrid;

class AnalyticVelocity {
 public:
  enum class Kind { TaylorGreen, RigidRotation, Deformation };

  static sdk::Schema schema();
  AnalyticVelocity() = default;
  /// `params`: validated against schema(); the field is fitted to `grid`'s box. ConfigError
  /// at `json_path`/... for what the schema cannot check (a zero axis).
  AnalyticVelocity(const nlohmann::json& params, const grid::UniformGrid& grid,
                   const std::string& json_path = "");

  /// The velocity at `x` [m/s] at time `t` [s].
  Eigen::Vector3d velocity(const Eigen::Vector3d& x, double t = 0.0) const;
  /// Sets every face's normal velocity to the field's component at the face's centre at t.
  void fill(MacGrid& mac, double t = 0.0) const;
  /// Does the field change with time (the nodes must be sampled again every step)?
  bool steady() const { return m_kind != Kind::Deformation; }

 private:
  Kind m_kind = Kind::TaylorGreen;
  Eigen::Vector3d m_lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d m_size = Eigen::Vector3d::Ones();
  double m_amplitude = 0.0;  ///< U (taylor_green)
  double m_gradient = 0.0;   ///< G (taylor_green)
  Eigen::Vector3d m_center = Eigen::Vector3d::Zero();  ///< c (rigid_rotation)
  Eigen::Vector3d m_omega = Eigen::Vector3d::Zero();   ///< ω (rigid_rotation)
  double m_period = 1.0;                               ///< T (deformation)
};

}  // namespace shellflow::grid_fluid
