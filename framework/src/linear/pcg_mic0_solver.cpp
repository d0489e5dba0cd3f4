#include "shellflow/linear/pcg_mic0_solver.hpp"

#include <string>

#include "shellflow/linear/linear_operator.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {

PcgMic0Solver::PcgMic0Solver(double mic_tau, double mic_sigma)
    : m_preconditioner(mic_tau, mic_sigma) {}

void PcgMic0Solver::compute(const SparseMatrix& A) {
  if (A.rows() != A.cols()) {
    throw Error("PcgMic0Solver::compute: the matrix must be square, got " +
                std::to_string(A.rows()) + " x " + std::to_string(A.cols()));
  }
  m_computed = false;
  m_a = A;
  m_a.makeCompressed();
  m_preconditioner.compute(m_a);
  m_computed = true;
}

void PcgMic0Solver::apply_preconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  m_preconditioner.apply(r, z);
}

SolveStats PcgMic0Solver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                double relative_tolerance, int max_iterations) const {
  if (!m_computed) throw Error("PcgMic0Solver::solve: call compute(A) first");
  if (b.size() != size()) {
    throw Error("PcgMic0Solver::solve: right-hand side has " + std::to_string(b.size()) +
                " entries, the matrix has " + std::to_string(size()) + " rows");
  }
  return preconditioned_cg(CsrOperator(m_a), m_preconditioner, b, x, relative_tolerance,
                           max_iterations);
}

}  // namespace shellflow::linear
