#pragma once
// CholmodSolver: a direct sparse Cholesky solve through SuiteSparse CHOLMOD (supernodal
// LL^T, Chen, Davis, Hager & Rajamanickam, ACM TOMS 2008) — the reference pressure
// solve for small grids (§4.3, Guendelman et al. 2005). CHOLMOD stays out of this
// header (pimpl); libshellflow links it privately.

#include <Eigen/Core>
#include <memory>

#include "shellflow/linear/solve_stats.hpp"
#include "shellflow/linear/sparse_matrix.hpp"

namespace shellflow::linear {

class CholmodSolver {
 public:
  CholmodSolver();
  ~CholmodSolver();
  CholmodSolver(CholmodSolver&&) noexcept;
  CholmodSolver& operator=(CholmodSolver&&) noexcept;
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  /// Analyses and factors `A` (square, symmetric; only its lower triangle is read).
  /// @throw shellflow::Error if A is not square, or not positive definite (the message
  /// names the column where the factorisation broke down; a singular all-Neumann
  /// matrix needs one pressure pinned, or PcgMic0Solver, instead).
  void compute(const SparseMatrix& A);

  /// Solves A x = b with the factor. `x` is overwritten (its entry value is ignored).
  /// Returns iterations = 0, the recomputed |b - A x| / |b| (0 when b = 0, then x = 0),
  /// converged = true. @throw shellflow::Error if compute() has not succeeded or b has
  /// the wrong size.
  SolveStats solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace shellflow::linear
