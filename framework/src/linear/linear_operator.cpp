#include "shellflow/linear/linear_operator.hpp"

#include "parallel_threshold.hpp"

namespace shellflow::linear {

using detail::kParallelThreshold;

double CsrOperator::multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int n = size();
  const int* start = m_a->outerIndexPtr();
  const int* column = m_a->innerIndexPtr();
  const double* value = m_a->valuePtr();
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

double CsrOperator::residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                             Eigen::VectorXd& r) const {
  const int n = size();
  const int* start = m_a->outerIndexPtr();
  const int* column = m_a->innerIndexPtr();
  const double* value = m_a->valuePtr();
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

}  // namespace shellflow::linear
