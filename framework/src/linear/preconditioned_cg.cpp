#include "shellflow/linear/preconditioned_cg.hpp"

#include <cmath>
#include <string>

#include "parallel_threshold.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {
namespace {

using detail::kParallelThreshold;

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

SolveStats preconditioned_cg(const LinearOperator& A, const Preconditioner& M,
                             const Eigen::VectorXd& b, Eigen::VectorXd& x,
                             double relative_tolerance, int max_iterations,
                             const ConstantNullSpace* null_space, PcgWorkspace* workspace) {
  const int n = A.size();
  if (b.size() != n || M.size() != n) {
    throw Error("preconditioned_cg: the operator has " + std::to_string(n) +
                " rows, the right-hand side " + std::to_string(b.size()) +
                " entries, the preconditioner " + std::to_string(M.size()) + " unknowns");
  }
  if (x.size() != n) x = Eigen::VectorXd::Zero(n);

  SolveStats stats;
  const double b_norm = std::sqrt(dot(b, b));
  if (b_norm == 0.0) {
    x.setZero();
    stats.converged = true;
    return stats;
  }

  PcgWorkspace local;
  PcgWorkspace& work = workspace != nullptr ? *workspace : local;
  for (Eigen::VectorXd* v : {&work.r, &work.z, &work.p, &work.q}) v->resize(n);
  Eigen::VectorXd &r = work.r, &z = work.z, &p = work.p, &q = work.q;
  double relative = std::sqrt(A.residual(b, x, r)) / b_norm;
  bool relative_is_true = true;  // `relative` was computed from b - A x, not recursively
  bool restart = true;
  double rz = 0.0;
  // Convergence is tested on the recursive residual and confirmed on the true one,
  // b - A x, which is what gets reported; if they disagree CG restarts from the true
  // residual.
  while (true) {
    if (relative <= relative_tolerance) {
      if (!relative_is_true) {
        relative = std::sqrt(A.residual(b, x, r)) / b_norm;
        relative_is_true = true;
      }
      if (relative <= relative_tolerance) break;
      restart = true;
    }
    if (stats.iterations >= max_iterations) break;
    M.apply(r, z);
    if (null_space != nullptr) null_space->project(z);
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
    const double pq = A.multiply_and_dot(p, q);
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
  if (!relative_is_true) relative = std::sqrt(A.residual(b, x, r)) / b_norm;
  stats.relative_residual = relative;
  stats.converged = stats.relative_residual <= relative_tolerance;
  return stats;
}

}  // namespace shellflow::linear
