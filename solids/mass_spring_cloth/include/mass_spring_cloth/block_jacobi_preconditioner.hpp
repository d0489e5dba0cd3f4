#pragma once
// Block-Jacobi preconditioner for the implicit cloth system: z_i = A_ii^{-1} r_i with the
// 3x3 diagonal block of each node. Against the scalar diagonal (Jacobi) it also undoes
// the coupling of a node's own x, y, z through its springs' u u^T terms, which is what a
// stiff, stretched spring adds to the diagonal block; each block of the SPD system is SPD,
// so its inverse is too and CG stays valid.

#include <Eigen/Core>
#include <vector>

#include "mass_spring_cloth/block_sparse_matrix.hpp"
#include "shellflow/linear/preconditioner.hpp"

namespace shellflow::cloth {

/// z = M^{-1} r for linear::preconditioned_cg on the block system; M symmetric positive
/// definite.
using BlockPreconditioner = linear::Preconditioner;

class BlockJacobiPreconditioner final : public BlockPreconditioner {
 public:
  /// Inverts the diagonal blocks of `a` (throws NumericalError if one is singular).
  void compute(const BlockSparseMatrix& a);
  int size() const override { return 3 * static_cast<int>(m_inverse.size()); }
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

 private:
  std::vector<Eigen::Matrix3d> m_inverse;
};

}  // namespace shellflow::cloth
