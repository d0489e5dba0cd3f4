#pragma once
// Rigid two-way shells moved as one body in the §5.1 coupling solve.
//
// §5.1 gives every face a shell cuts the density σ/Δx of the shell there, so each face
// yields to the fluid on its own. For cloth that is the model; for a rigid hull it is not:
// the walls of an open boat, each yielding alone, let the water drain into the hull in the
// solve, and the boat sinks. A rigid shell's faces instead all move with the body's one
// velocity V: the face f of axis a moves at J_f V, J_f = [e_a; r_f × e_a]ᵀ (r_f from the
// centre of mass; in water the pieces of shell the face stands for, rigid_face_areas.hpp),
// and the body takes the impulse of the jumps, Δx² Δt Σ_f −[p]_f J_fᵀ. With q = p Δt/(ρ Δx)
// and K q = −Σ_f J_fᵀ [q]_f, the solve for q becomes
//     (L + ρ Δx³ Σ_bodies Kᵀ 𝓜⁻¹ K) q = b,
// L the fluid faces' Laplacian (a rigid face has weight 0 in it), 𝓜⁻¹ the body's inverse
// mass and inertia. The body's faces enter b through Kᵀ too (−Kᵀ V*, V* what the body would
// do without the fluid: its velocity plus its gravity over the step), so a body at rest in
// still water, with the hydrostatic q, is an exact solution exactly when it weighs what
// the water it keeps out weighs (Archimedes). The operator stays symmetric positive
// semidefinite (L plus a sum of rank-6 terms), so CG with L's multigrid V-cycle serves:
// the rank-6 terms cost a few iterations each, not a new preconditioner.
// The body then gets exactly the wrench of the solve (ρ Δx³/Δt K q): the triangle forces
// of steps 3–4 are corrected to it, or a light body would take the spread error of those
// steps as a net force (a plate of σ = 10⁻³ ρΔx drifted and gained energy from it).
//
// [q]_f is the jump at the shell as the coupling reads it (CouplingPressure): between the
// cell centres for smoke, each side extrapolated to the shell for water, a linear form in
// up to four cells' q (FaceJump).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/linear/grid_laplacian.hpp"

namespace shellflow::grid_fluid {

/// [q]_f = Σ weight · q[cell] over up to four cells (two per side of the shell).
struct FaceJump {
  std::array<std::int64_t, 4> cell{};
  std::array<double, 4> weight{};
  int count = 0;

  void add(std::int64_t c, double w) {
    cell[count] = c;
    weight[count] = w;
    ++count;
  }
  template <class Vector>
  double of(const Vector& q) const {
    double sum = 0.0;
    for (int k = 0; k < count; ++k) sum += weight[k] * q[cell[k]];
    return sum;
  }
  /// y += value · ∂[q]/∂q: the transpose of of().
  void scatter(double value, Eigen::VectorXd& y) const {
    for (int k = 0; k < count; ++k) y[cell[k]] += weight[k] * value;
  }
};

using BodyVector = Eigen::Matrix<double, 6, 1>;  ///< [linear; angular]

/// One rigid shell in the coupling solve: the body, and the faces it cuts.
struct RigidShellFaces {
  Eigen::Matrix<double, 6, 6> inverse_mass = Eigen::Matrix<double, 6, 6>::Zero();  ///< 𝓜⁻¹
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();    ///< without the fluid [m/s²]
  std::vector<double> triangle_area;              ///< per triangle [m²]
  std::vector<Eigen::Vector3d> triangle_centre;   ///< per triangle: its barycentre [m]
  std::vector<FaceJump> jumps;       ///< per face
  /// J_fᵀ per face, scaled by the shell area it stands for over Δx² (rigid_face_areas.hpp)
  std::vector<BodyVector> rows;
  /// K q = −Σ_f J_fᵀ [q]_f.
  BodyVector impulse(const Eigen::Ref<const Eigen::VectorXd>& q) const;
  /// y += Kᵀ w = −Σ_f (J_f w) ∂[q]_f/∂q: the transpose of impulse().
  void add_transpose(const BodyVector& w, Eigen::VectorXd& y) const;
};

/// L + c Σ Kᵀ 𝓜⁻¹ K with c = ρ Δx³, over the bodies' faces.
class RigidShellOperator final : public linear::LinearOperator {
 public:
  RigidShellOperator(const linear::GridLaplacian& laplacian,
                     const std::vector<RigidShellFaces>& bodies, double fluid_cell_mass)
      : m_laplacian(laplacian), m_bodies(bodies), m_cell_mass(fluid_cell_mass) {}

  int size() const override { return m_laplacian.size(); }
  double multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
  double residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                  Eigen::VectorXd& r) const override;

 private:
  const linear::GridLaplacian& m_laplacian;
  const std::vector<RigidShellFaces>& m_bodies;
  double m_cell_mass;
};

}  // namespace shellflow::grid_fluid
