#include "shellflow/linear/pcg_mic0_solver.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {
namespace {

// Below this many unknowns the OpenMP fork/join costs more than the loop (small
// enclosed regions are solved on their own, §4.3), so the loops run on one thread.
constexpr int kParallelThreshold = 8192;

// y = A x over the rows of a compressed CSR matrix; returns x . y (fused, one pass).
double multiply_and_dot(const SparseMatrix& a, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  const int n = static_cast<int>(a.rows());
  const int* start = a.outerIndexPtr();
  const int* column = a.innerIndexPtr();
  const double* value = a.valuePtr();
  const double* xp = x.data();
  double* yp = y.data();
  double dot = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : dot) if (n >= kParallelThreshold)
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int p = start[i]; p < start[i + 1]; ++p) sum += value[p] * xp[column[p]];
    yp[i] = sum;
    dot += xp[i] * sum;
  }
  return dot;
}

// r = b - A x; returns |r|^2.
double residual(const SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                Eigen::VectorXd& r) {
  const int n = static_cast<int>(a.rows());
  const int* start = a.outerIndexPtr();
  const int* column = a.innerIndexPtr();
  const double* value = a.valuePtr();
  const double* xp = x.data();
  const double* bp = b.data();
  double* rp = r.data();
  double norm2 = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : norm2) if (n >= kParallelThreshold)
  for (int i = 0; i < n; ++i) {
    double sum = bp[i];
    for (int p = start[i]; p < start[i + 1]; ++p) sum -= value[p] * xp[column[p]];
    rp[i] = sum;
    norm2 += sum * sum;
  }
  return norm2;
}

double dot(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  const int n = static_cast<int>(u.size());
  const double* up = u.data();
  const double* vp = v.data();
  double sum = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : sum) if (n >= kParallelThreshold)
  for (int i = 0; i < n; ++i) sum += up[i] * vp[i];
  return sum;
}

}  // namespace

PcgMic0Solver::PcgMic0Solver(double mic_tau, double mic_sigma)
    : m_tau(mic_tau), m_sigma(mic_sigma) {
  if (!(mic_tau >= 0.0 && mic_tau <= 1.0)) {
    throw Error("PcgMic0Solver: mic_tau must lie in [0, 1] (0: IC(0), Bridson uses 0.97); got " +
                std::to_string(mic_tau));
  }
  if (!(mic_sigma >= 0.0 && mic_sigma < 1.0)) {
    throw Error("PcgMic0Solver: mic_sigma must lie in [0, 1) (Bridson uses 0.25); got " +
                std::to_string(mic_sigma));
  }
}

void PcgMic0Solver::compute(const SparseMatrix& A) {
  if (A.rows() != A.cols()) {
    throw Error("PcgMic0Solver::compute: the matrix must be square, got " +
                std::to_string(A.rows()) + " x " + std::to_string(A.cols()));
  }
  m_computed = false;
  m_a = A;
  m_a.makeCompressed();
  const int n = static_cast<int>(m_a.rows());
  const int* start = m_a.outerIndexPtr();
  const int* column = m_a.innerIndexPtr();
  const double* value = m_a.valuePtr();

  // U starts as the strictly upper part of A; `pivot` as its diagonal.
  std::vector<double> diagonal(n, 0.0);
  m_upper_start.assign(n + 1, 0);
  m_upper_column.clear();
  m_upper_value.clear();
  for (int i = 0; i < n; ++i) {
    for (int p = start[i]; p < start[i + 1]; ++p) {
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
  m_computed = true;
}

void PcgMic0Solver::apply_preconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
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

SolveStats PcgMic0Solver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                double relative_tolerance, int max_iterations) const {
  if (!m_computed) throw Error("PcgMic0Solver::solve: call compute(A) first");
  const int n = size();
  if (b.size() != n) {
    throw Error("PcgMic0Solver::solve: right-hand side has " + std::to_string(b.size()) +
                " entries, the matrix has " + std::to_string(n) + " rows");
  }
  if (x.size() != n) x = Eigen::VectorXd::Zero(n);

  SolveStats stats;
  const double b_norm = std::sqrt(dot(b, b));
  if (b_norm == 0.0) {
    x.setZero();
    stats.converged = true;
    return stats;
  }

  Eigen::VectorXd r(n), z(n), p(n), q(n);
  double relative = std::sqrt(residual(m_a, b, x, r)) / b_norm;
  bool relative_is_true = true;  // `relative` was computed from b - A x, not recursively
  bool restart = true;
  double rz = 0.0;
  // Conjugate gradients (Hestenes–Stiefel 1952) with preconditioner M; convergence is
  // tested on the recursive residual and confirmed on the true one, b - A x, which is
  // what gets reported; if they disagree CG restarts from the true residual.
  while (true) {
    if (relative <= relative_tolerance) {
      if (!relative_is_true) {
        relative = std::sqrt(residual(m_a, b, x, r)) / b_norm;
        relative_is_true = true;
      }
      if (relative <= relative_tolerance) break;
      restart = true;
    }
    if (stats.iterations >= max_iterations) break;
    apply_preconditioner(r, z);
    const double rz_new = dot(r, z);
    if (restart) {
      p = z;
      restart = false;
    } else {
      const double beta = rz_new / rz;
      double* pp = p.data();
      const double* zp = z.data();
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
      for (int i = 0; i < n; ++i) pp[i] = zp[i] + beta * pp[i];
    }
    rz = rz_new;
    const double pq = multiply_and_dot(m_a, p, q);
    if (!(pq > 0.0) || !(rz > 0.0)) break;  // breakdown: A or M not positive on p
    const double alpha = rz / pq;
    double r_norm2 = 0.0;
    double* xp = x.data();
    double* rp = r.data();
    const double* pp = p.data();
    const double* qp = q.data();
#pragma omp parallel for schedule(static) reduction(+ : r_norm2) if (n >= kParallelThreshold)
    for (int i = 0; i < n; ++i) {
      xp[i] += alpha * pp[i];
      rp[i] -= alpha * qp[i];
      r_norm2 += rp[i] * rp[i];
    }
    ++stats.iterations;
    relative = std::sqrt(r_norm2) / b_norm;
    relative_is_true = false;
  }
  if (!relative_is_true) relative = std::sqrt(residual(m_a, b, x, r)) / b_norm;
  stats.relative_residual = relative;
  stats.converged = stats.relative_residual <= relative_tolerance;
  return stats;
}

}  // namespace shellflow::linear
