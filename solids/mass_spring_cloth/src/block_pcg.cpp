#include "mass_spring_cloth/block_pcg.hpp"

#include <cmath>

namespace shellflow::cloth {

namespace {

constexpr int kParallelThreshold = 24576;

double dot(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  const int n = static_cast<int>(u.size());
  double sum = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : sum) if (n >= kParallelThreshold)
  for (int i = 0; i < n; ++i) sum += u[i] * v[i];
  return sum;
}

}  // namespace

PcgResult block_pcg(const BlockSparseMatrix& a, const BlockPreconditioner& m,
                    const Eigen::VectorXd& b, Eigen::VectorXd& x, double tolerance,
                    int max_iterations) {
  const int n = a.size();
  PcgResult result;
  if (x.size() != n) x = Eigen::VectorXd::Zero(n);
  const double b_norm = std::sqrt(dot(b, b));
  if (b_norm == 0.0) {
    x.setZero();
    return result;
  }
  Eigen::VectorXd r(n), z(n), p(n), q(n);
  double relative = std::sqrt(a.residual(b, x, r)) / b_norm;
  bool relative_is_true = true;
  bool restart = true;
  double rz = 0.0;
  // Convergence is tested on the recursive residual and confirmed on the true one; if
  // they disagree CG restarts from the true residual.
  while (true) {
    if (relative <= tolerance) {
      if (!relative_is_true) {
        relative = std::sqrt(a.residual(b, x, r)) / b_norm;
        relative_is_true = true;
      }
      if (relative <= tolerance) break;
      restart = true;
    }
    if (result.iterations >= max_iterations) break;
    m.apply(r, z);
    const double rz_new = dot(r, z);
    if (restart) {
      p = z;
      restart = false;
    } else {
      const double beta = rz_new / rz;
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
      for (int i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    }
    rz = rz_new;
    const double pq = a.multiply_and_dot(p, q);
    if (!(pq > 0.0) || !(rz > 0.0)) break;  // breakdown: A or M not positive on p
    const double alpha = rz / pq;
    double r_norm2 = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : r_norm2) if (n >= kParallelThreshold)
    for (int i = 0; i < n; ++i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
      r_norm2 += r[i] * r[i];
    }
    ++result.iterations;
    relative = std::sqrt(r_norm2) / b_norm;
    relative_is_true = false;
  }
  if (!relative_is_true) relative = std::sqrt(a.residual(b, x, r)) / b_norm;
  result.relative_residual = relative;
  return result;
}

}  // namespace shellflow::cloth
