#pragma once
// Two-level preconditioner for the implicit cloth system: block Jacobi (each node's 3x3
// diagonal block) plus a coarse correction on aggregates of nodes, added together
// (additive two-level Schwarz; Toselli and Widlund, "Domain Decomposition Methods" 2005,
// §2.2; aggregates as in Vaněk, Mandel, Brezina 1996, "Algebraic multigrid by smoothed
// aggregation", without the smoothing):
//   z = D^{-1} r + P (P^T A P)^{-1} P^T r,
// with P the piecewise-constant prolongation: node i moves with the translation of its
// aggregate. Stiff springs make the implicit matrix M + h^2 K dominated by the membrane
// stiffness, whose smooth modes a local preconditioner only reaches after as many CG
// iterations as the stress wave crosses nodes; the coarse space carries those modes in
// one solve. The coarse matrix (3 unknowns per aggregate, a few thousand) is factored by
// Eigen's simplicial LLT, whose symbolic analysis is done once. (CHOLMOD's supernodal
// factor was no faster at this size, and its BLAS threads stall badly when the two
// cores are shared: the 64x64 test went from 2 s to 5-20 s under load.) Both terms are SPD on
// the free nodes, so CG stays valid; constrained nodes are left out of the coarse space.

#include <Eigen/SparseCholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "mass_spring_cloth/block_jacobi_preconditioner.hpp"
#include "mass_spring_cloth/block_sparse_matrix.hpp"

namespace shellflow::cloth {

class AggregationPreconditioner final : public BlockPreconditioner {
 public:
  /// Aggregates from the pattern of `a` (a node and its unaggregated neighbours, greedy;
  /// leftovers join a neighbouring aggregate) and the coarse pattern. Once per pattern.
  void build(const BlockSparseMatrix& a);
  /// Block-Jacobi inverses and the coarse matrix P^T A P over the nodes not `fixed`,
  /// factored. Throws NumericalError if a block or the coarse matrix is not SPD.
  void compute(const BlockSparseMatrix& a, const std::vector<char>& fixed);
  int size() const override { return m_jacobi.size(); }
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

  int aggregate_count() const { return m_aggregate_count; }

 private:
  BlockJacobiPreconditioner m_jacobi;
  std::vector<int> m_aggregate;  ///< per node; -1 while the node is fixed
  std::vector<int> m_base_aggregate;
  int m_aggregate_count = 0;
  BlockSparseMatrix m_coarse;      ///< P^T A P, one block per pair of adjacent aggregates
  std::vector<int> m_coarse_slot;  ///< per fine block, its block in m_coarse
  std::vector<int> m_free_count;   ///< per aggregate, its nodes that are not fixed
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower> m_factor;
  bool m_analysed = false;
};

}  // namespace shellflow::cloth
