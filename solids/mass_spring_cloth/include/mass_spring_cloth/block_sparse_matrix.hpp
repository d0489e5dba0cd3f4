#pragma once
// A symmetric 3x3-block sparse matrix over the cloth nodes with a fixed pattern, stored
// as an Eigen row-major CSR matrix so that the CG's matrix-vector product runs in
// parallel. Each block (i, j) is reached through a Slot found once: entry (3i+a, 3j+b)
// lives at values[slot.position + a * slot.row_stride + b].

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <utility>
#include <vector>

namespace shellflow::cloth {

class BlockSparseMatrix {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  struct Slot {
    int position = 0;
    int row_stride = 0;
  };

  /// Pattern: every diagonal block plus both (i,j) and (j,i) for each listed pair.
  void build(int node_count, const std::vector<std::pair<int, int>>& pairs);
  Slot slot(int i, int j) const;

  void set_zero() { m_matrix.coeffs().setZero(); }
  void add(Slot s, const Eigen::Matrix3d& block) {
    double* v = m_matrix.valuePtr() + s.position;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) v[a * s.row_stride + b] += block(a, b);
  }
  void add_diagonal(Slot s, double value) {
    double* v = m_matrix.valuePtr() + s.position;
    for (int a = 0; a < 3; ++a) v[a * s.row_stride + a] += value;
  }

  Matrix& matrix() { return m_matrix; }
  const Matrix& matrix() const { return m_matrix; }
  int node_count() const { return m_node_count; }

 private:
  Matrix m_matrix;
  int m_node_count = 0;
};

}  // namespace shellflow::cloth
