#pragma once
// LinearOperator: y = A x for a symmetric positive (semi)definite A, given as a matrix
// (CsrOperator) or matrix-free (GridLaplacian, the 7-point pressure stencil of the MAC
// grid, §4.3 of Guendelman et al. 2005). preconditioned_cg() iterates on this interface.

#include <Eigen/Core>

#include "shellflow/linear/sparse_matrix.hpp"

namespace shellflow::linear {

class LinearOperator {
 public:
  virtual ~LinearOperator() = default;
  /// Number of rows (= columns).
  virtual int size() const = 0;
  /// y = A x; returns x · y (CG needs both; one fused pass saves a sweep over memory).
  /// `y` has size() entries on entry.
  virtual double multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const = 0;
  /// r = b − A x; returns |r|^2. `r` has size() entries on entry.
  virtual double residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                          Eigen::VectorXd& r) const = 0;
};

/// A compressed row matrix (full symmetric pattern) as a LinearOperator. Keeps a reference:
/// the matrix must outlive the operator.
class CsrOperator final : public LinearOperator {
 public:
  explicit CsrOperator(const SparseMatrix& a) : m_a(&a) {}
  int size() const override { return static_cast<int>(m_a->rows()); }
  double multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
  double residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                  Eigen::VectorXd& r) const override;

 private:
  const SparseMatrix* m_a;
};

}  // namespace shellflow::linear
