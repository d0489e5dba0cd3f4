#pragma once
// Preconditioned conjugate gradients (Hestenes & Stiefel 1952; Saad, "Iterative Methods
// for Sparse Linear Systems" 2003, Alg. 9.1) on any LinearOperator with any
// Preconditioner, in double precision, with OpenMP vector kernels. The pressure solve of
// the MAC-grid projection (§4.3, Guendelman et al. 2005) runs through it with MIC(0) or
// multigrid.

#include <Eigen/Core>

#include "shellflow/linear/constant_null_space.hpp"
#include "shellflow/linear/linear_operator.hpp"
#include "shellflow/linear/preconditioner.hpp"
#include "shellflow/linear/solve_stats.hpp"

namespace shellflow::linear {

/// The work vectors of preconditioned_cg, for a caller that solves every step: fresh
/// vectors of a 128³ grid's 2M unknowns cost a page fault per 4 KiB on every solve.
struct PcgWorkspace {
  Eigen::VectorXd r, z, p, q;
};

/// Solves A x = b. `x` is the initial guess on entry (resized and zeroed if its size
/// differs from A's) and the solution on return. Stops when |b − A x| / |b| <=
/// `relative_tolerance` (confirmed on the true residual, which is what is reported) or
/// after `max_iterations`; |b| = 0 gives x = 0. For a semidefinite A the caller makes b
/// consistent; `null_space` (may be null) is then projected out of every preconditioned
/// residual. `workspace` (may be null) holds the work vectors between calls. Throws
/// shellflow::Error if sizes disagree.
SolveStats preconditioned_cg(const LinearOperator& A, const Preconditioner& M,
                             const Eigen::VectorXd& b, Eigen::VectorXd& x,
                             double relative_tolerance, int max_iterations,
                             const ConstantNullSpace* null_space = nullptr,
                             PcgWorkspace* workspace = nullptr);

}  // namespace shellflow::linear
