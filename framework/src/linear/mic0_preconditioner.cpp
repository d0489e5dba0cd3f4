#include "shellflow/linear/mic0_preconditioner.hpp"

#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {

Mic0Preconditioner::Mic0Preconditioner(double tau, double sigma) : m_tau(tau), m_sigma(sigma) {
  if (!(tau >= 0.0 && tau <= 1.0)) {
    throw Error("MIC(0): mic_tau must lie in [0, 1] (0: IC(0), Bridson uses 0.97); got " +
                std::to_string(tau));
  }
  if (!(sigma >= 0.0 && sigma < 1.0)) {
    throw Error("MIC(0): mic_sigma must lie in [0, 1) (Bridson uses 0.25); got " +
                std::to_string(sigma));
  }
}

void Mic0Preconditioner::compute(const SparseMatrix& A) {
  if (A.rows() != A.cols()) {
    throw Error("MIC(0) compute: the matrix must be square, got " + std::to_string(A.rows()) +
                " x " + std::to_string(A.cols()));
  }
  const int n = static_cast<int>(A.rows());
  const int* start = A.outerIndexPtr();
  const int* nonzeros = A.innerNonZeroPtr();  // null when compressed
  const int* column = A.innerIndexPtr();
  const double* value = A.valuePtr();

  // U starts as the strictly upper part of A; `pivot` as its diagonal.
  std::vector<double> diagonal(n, 0.0);
  m_upper_start.assign(n + 1, 0);
  m_upper_column.clear();
  m_upper_value.clear();
  m_upper_column.reserve(A.nonZeros() / 2 + 1);
  m_upper_value.reserve(A.nonZeros() / 2 + 1);
  for (int i = 0; i < n; ++i) {
    const int end = nonzeros ? start[i] + nonzeros[i] : start[i + 1];
    for (int p = start[i]; p < end; ++p) {
      if (column[p] == i) diagonal[i] += value[p];
      if (column[p] > i) {
        m_upper_column.push_back(column[p]);
        m_upper_value.push_back(value[p]);
      }
    }
    m_upper_start[i + 1] = static_cast<int>(m_upper_column.size());
  }
  std::vector<double> pivot = diagonal;
  m_inverse_pivot.assign(n, 0.0);

  // Right-looking incomplete factorisation on the pattern of A (Bridson 2008, §4.3.2,
  // "MIC(0)", there written for the 7-point stencil, where no fill lands in the
  // pattern). Eliminating row k updates u_jl -= u_kj u_kl / d_k for j <= l in row k;
  // an update outside the pattern is dropped and tau times it is subtracted from the
  // pivots of both rows it would have touched (row sums kept for tau = 1).
  for (int k = 0; k < n; ++k) {
    double d = pivot[k];
    if (!(diagonal[k] > 0.0)) {
      d = 1.0;  // empty row of a semidefinite matrix: identity pivot
    } else if (!(d >= m_sigma * diagonal[k])) {
      d = diagonal[k];  // Bridson's guard against tiny or negative pivots
    }
    m_inverse_pivot[k] = 1.0 / d;
    const int row_begin = m_upper_start[k];
    const int row_end = m_upper_start[k + 1];
    for (int p = row_begin; p < row_end; ++p) {
      const int j = m_upper_column[p];
      const double ukj_over_d = m_upper_value[p] / d;
      pivot[j] -= ukj_over_d * m_upper_value[p];
      int search = m_upper_start[j];  // row j's columns are sorted: advance monotonically
      const int search_end = m_upper_start[j + 1];
      for (int q = p + 1; q < row_end; ++q) {
        const int l = m_upper_column[q];
        const double fill = ukj_over_d * m_upper_value[q];
        while (search < search_end && m_upper_column[search] < l) ++search;
        if (search < search_end && m_upper_column[search] == l) {
          m_upper_value[search] -= fill;
        } else {
          pivot[j] -= m_tau * fill;
          pivot[l] -= m_tau * fill;
        }
      }
    }
  }
}

void Mic0Preconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  // M = (D + U^T) D^{-1} (D + U). Both triangular sweeps are sequential: each unknown
  // depends on the previous ones in the natural ordering.
  const int n = size();
  z = r;
  // Forward: (D + U^T) w = r, column-oriented through the rows of U; w overwrites z.
  for (int k = 0; k < n; ++k) {
    const double wk = z[k] * m_inverse_pivot[k];
    z[k] = wk;
    for (int p = m_upper_start[k]; p < m_upper_start[k + 1]; ++p) {
      z[m_upper_column[p]] -= m_upper_value[p] * wk;
    }
  }
  // Backward: (D + U) z = D w  ->  z_i = w_i - (sum_{j>i} u_ij z_j) / d_i.
  for (int i = n - 1; i >= 0; --i) {
    double sum = 0.0;
    for (int p = m_upper_start[i]; p < m_upper_start[i + 1]; ++p) {
      sum += m_upper_value[p] * z[m_upper_column[p]];
    }
    z[i] -= sum * m_inverse_pivot[i];
  }
}

}  // namespace shellflow::linear
