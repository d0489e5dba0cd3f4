#pragma once
// Mic0Preconditioner: the modified incomplete Cholesky factorisation MIC(0) as a
// Preconditioner. After Bridson & Müller-Fischer, "Fluid Simulation", SIGGRAPH 2007
// course notes §4 (Bridson, "Fluid Simulation for Computer Graphics" 2008, ch. 4.3.2),
// generalised from the 7-point stencil to any matrix with a full symmetric pattern:
//   A ≈ (D + U^T) D^{-1} (D + U),  U strictly upper on the pattern of A,
// where fill-in that falls outside the pattern is dropped and a fraction tau of it is
// moved to the diagonal (tau = 0: IC(0), tau = 1: row sums kept, MIC). A pivot below
// sigma times the original diagonal is replaced by that diagonal (Bridson's guard), so
// a singular but consistent all-Neumann system factors without dividing by zero.
// The factorisation and both triangular solves are sequential (natural ordering); the
// parallel alternative is MultigridPreconditioner.

#include <Eigen/Core>
#include <vector>

#include "shellflow/linear/preconditioner.hpp"
#include "shellflow/linear/sparse_matrix.hpp"

namespace shellflow::linear {

class Mic0Preconditioner final : public Preconditioner {
 public:
  /// `tau` in [0, 1], `sigma` in [0, 1); shellflow::Error otherwise.
  explicit Mic0Preconditioner(double tau = 0.97, double sigma = 0.25);

  /// Factors A (square, full symmetric pattern, compressed rows sorted). Rows with a
  /// non-positive diagonal (an empty row of a semidefinite matrix) get an identity pivot.
  /// Throws shellflow::Error if A is not square.
  void compute(const SparseMatrix& A);

  int size() const override { return static_cast<int>(m_inverse_pivot.size()); }
  /// z = M^{-1} r with M = (D + U^T) D^{-1} (D + U).
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

  double tau() const { return m_tau; }
  double sigma() const { return m_sigma; }

 private:
  double m_tau;
  double m_sigma;
  // Strictly upper part U of the factor, CSR: row i holds u_ij for j > i.
  std::vector<int> m_upper_start;
  std::vector<int> m_upper_column;
  std::vector<double> m_upper_value;
  // 1 / d_i for the pivots D.
  std::vector<double> m_inverse_pivot;
};

}  // namespace shellflow::linear
