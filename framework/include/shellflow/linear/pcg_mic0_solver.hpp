#pragma once
// PcgMic0Solver: conjugate gradients preconditioned with the modified incomplete
// Cholesky factorisation MIC(0), in double precision — the matrix form of the pressure
// solver of the MAC-grid projection (§4.3, Guendelman et al. 2005). It pairs a
// Mic0Preconditioner (the factorisation; see its header for the method, after Bridson
// 2008, ch. 4.3.2) with preconditioned_cg() on a CsrOperator.
//
// Threads: the matrix-vector product and the vector operations of CG run with OpenMP;
// the factorisation and the two triangular solves of MIC(0) are sequential (the parallel
// alternative for grid problems is MultigridPreconditioner on a GridLaplacian).

#include <Eigen/Core>
#include <vector>

#include "shellflow/linear/mic0_preconditioner.hpp"
#include "shellflow/linear/solve_stats.hpp"
#include "shellflow/linear/sparse_matrix.hpp"

namespace shellflow::linear {

class PcgMic0Solver {
 public:
  /// `mic_tau` in [0, 1]: fraction of dropped fill moved to the diagonal (Bridson: 0.97).
  /// `mic_sigma` in [0, 1): pivot guard, pivots below sigma * a_ii are reset to a_ii
  /// (Bridson: 0.25). Throws shellflow::Error for values outside these ranges.
  explicit PcgMic0Solver(double mic_tau = 0.97, double mic_sigma = 0.25);

  /// Factors the MIC(0) preconditioner of `A` (square, full symmetric pattern, sorted
  /// compressed rows) and keeps a copy of A for the iterations. Throws shellflow::Error
  /// if A is not square. Rows with a non-positive diagonal (an empty row of a
  /// semidefinite matrix) get an identity pivot.
  void compute(const SparseMatrix& A);

  /// Solves A x = b by PCG. `x` is the initial guess on entry (resized and zeroed if its
  /// size differs from A's) and the solution on return. Stops when
  /// |b - A x| / |b| <= `relative_tolerance` (checked on the true residual) or after
  /// `max_iterations`. |b| = 0 gives x = 0. For a singular (all-Neumann) A the caller
  /// must make b consistent (orthogonal to the null space). Throws shellflow::Error if
  /// compute() has not been called or b has the wrong size.
  SolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double relative_tolerance,
                   int max_iterations) const;

  /// Applies the preconditioner: z = M^{-1} r with M = (D + U^T) D^{-1} (D + U).
  void apply_preconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;

  double mic_tau() const { return m_preconditioner.tau(); }
  double mic_sigma() const { return m_preconditioner.sigma(); }
  /// Number of unknowns of the factored matrix (0 before compute()).
  int size() const { return m_computed ? m_preconditioner.size() : 0; }
  /// The MIC(0) factorisation (valid after compute()).
  const Mic0Preconditioner& preconditioner() const { return m_preconditioner; }

 private:
  Mic0Preconditioner m_preconditioner;
  bool m_computed = false;
  SparseMatrix m_a;
};

}  // namespace shellflow::linear
