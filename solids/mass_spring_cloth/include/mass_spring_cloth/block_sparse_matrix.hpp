#pragma once
// A symmetric 3x3-block sparse matrix over the cloth nodes with a fixed pattern, in block
// compressed-row form (BSR): block row i holds the blocks (i, j) of its neighbours j in
// increasing order, each 3x3 block row-major in one flat array. The pattern is built once
// (springs and bending stencils do not change); every step only refills the values in
// place. Against a scalar CSR matrix of the same entries this stores one column index per
// 9 values, so the CG's matrix-vector product reads about 40% less memory, and a block
// row is one node, so the row-parallel product and the assembly's per-node gathers need no
// atomics.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <utility>
#include <vector>

#include "shellflow/linear/linear_operator.hpp"

namespace shellflow::cloth {

/// A linear::LinearOperator, so the framework's preconditioned_cg solves with it.
class BlockSparseMatrix final : public linear::LinearOperator {
 public:
  using Block = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;
  using ConstBlock = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;

  /// Pattern: every diagonal block plus both (i,j) and (j,i) for each listed pair.
  void build(int node_count, const std::vector<std::pair<int, int>>& pairs);
  /// Index of block (i, j) in the pattern (asserts that it is there).
  int find(int i, int j) const;
  int diagonal(int i) const { return m_diagonal[i]; }

  int node_count() const { return static_cast<int>(m_row_start.size()) - 1; }
  int block_count() const { return static_cast<int>(m_columns.size()); }
  int row_begin(int i) const { return m_row_start[i]; }
  int row_end(int i) const { return m_row_start[i + 1]; }
  int column(int b) const { return m_columns[b]; }

  void set_zero() { std::fill(m_values.begin(), m_values.end(), 0.0); }
  Block block(int b) { return Block(m_values.data() + 9 * b); }
  ConstBlock block(int b) const { return ConstBlock(m_values.data() + 9 * b); }
  void add_diagonal(int b, double value) {
    double* v = m_values.data() + 9 * b;
    v[0] += value, v[4] += value, v[8] += value;
  }

  /// Copies the diagonal and the upper blocks (j > i) into the compact symmetric form
  /// that the products below read: half the memory traffic of the full pattern, which is
  /// what bounds the CG's product. Call after the values are final for the solve.
  void compress_symmetric();

  // 3 unknowns per node; products with OpenMP (each thread its row range, scattering the
  // transposed blocks into its own buffer). Need compress_symmetric() after the last change.
  int size() const override { return 3 * node_count(); }
  /// y = A x; returns x . y.
  double multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
  /// r = b - A x; returns |r|^2.
  double residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                  Eigen::VectorXd& r) const override;

  /// The same matrix as a scalar column-major sparse matrix (for CHOLMOD). The scalar
  /// pattern is made on the first call; later calls only copy the values.
  const Eigen::SparseMatrix<double>& to_scalar();

 private:
  std::vector<int> m_row_start{0};
  std::vector<int> m_columns;
  std::vector<int> m_diagonal;
  std::vector<double> m_values;  ///< 9 per block, row-major
  // Compact symmetric form: per row, its upper blocks; and every diagonal block.
  std::vector<int> m_upper_start, m_upper_columns, m_upper_source;
  std::vector<double> m_upper_values, m_diagonal_values;
  mutable std::vector<Eigen::VectorXd> m_thread_products;
  void symmetric_product(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;

  Eigen::SparseMatrix<double> m_scalar;
  std::vector<int> m_scalar_source;  ///< per scalar nonzero, its index in m_values
};

}  // namespace shellflow::cloth
