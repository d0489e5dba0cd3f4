#pragma once
// Preconditioned conjugate gradients (Hestenes & Stiefel 1952; Saad 2003, Alg. 9.1) on
// the cloth's block system with a block preconditioner, with OpenMP vector
// kernels and a fused product-and-dot. Stops when |b - A x| / |b| <= tolerance,
// confirmed on the true residual. `x` is the initial guess on entry (the warm start).

#include <Eigen/Core>

#include "mass_spring_cloth/block_jacobi_preconditioner.hpp"
#include "mass_spring_cloth/block_sparse_matrix.hpp"

namespace shellflow::cloth {

struct PcgResult {
  int iterations = 0;
  double relative_residual = 0.0;  ///< |b - A x| / |b| of the returned x (0 when b = 0)
};

PcgResult block_pcg(const BlockSparseMatrix& a, const BlockPreconditioner& m,
                    const Eigen::VectorXd& b, Eigen::VectorXd& x, double tolerance,
                    int max_iterations);

}  // namespace shellflow::cloth
