#include "shellflow/linear/cholmod_solver.hpp"

#include <suitesparse/cholmod.h>

#include <cmath>
#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {

// The CHOLMOD workspace and factor. Not safe for concurrent solve() calls on one
// solver (cholmod_common is scratch space); use one CholmodSolver per thread.
struct CholmodSolver::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  SparseMatrix a;

  Impl() {
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SUPERNODAL;  // supernodal LL^T
    common.final_ll = 1;
    common.print = 0;  // failures are reported through shellflow::Error, not stdout
  }
  ~Impl() {
    release_factor();
    cholmod_finish(&common);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void release_factor() {
    if (factor != nullptr) cholmod_free_factor(&factor, &common);
    factor = nullptr;
  }

  // A view of `a` without copying. The CSR arrays of A read as CSC are A^T; stype = +1
  // makes CHOLMOD read the upper triangle of A^T, i.e. the lower triangle of A.
  cholmod_sparse view() {
    cholmod_sparse s{};
    s.nrow = static_cast<size_t>(a.rows());
    s.ncol = static_cast<size_t>(a.cols());
    s.nzmax = static_cast<size_t>(a.nonZeros());
    s.p = a.outerIndexPtr();
    s.i = a.innerIndexPtr();
    s.nz = nullptr;
    s.x = a.valuePtr();
    s.z = nullptr;
    s.stype = 1;
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }
};

CholmodSolver::CholmodSolver() : m_impl(std::make_unique<Impl>()) {}
CholmodSolver::~CholmodSolver() = default;
CholmodSolver::CholmodSolver(CholmodSolver&&) noexcept = default;
CholmodSolver& CholmodSolver::operator=(CholmodSolver&&) noexcept = default;

void CholmodSolver::compute(const SparseMatrix& A) {
  if (A.rows() != A.cols()) {
    throw Error("CholmodSolver::compute: the matrix must be square, got " +
                std::to_string(A.rows()) + " x " + std::to_string(A.cols()));
  }
  Impl& impl = *m_impl;
  impl.release_factor();
  impl.a = A;
  impl.a.makeCompressed();
  const long n = static_cast<long>(impl.a.rows());
  cholmod_sparse view = impl.view();
  impl.factor = cholmod_analyze(&view, &impl.common);
  if (impl.factor == nullptr) {
    throw Error("CholmodSolver::compute: CHOLMOD analysis failed (status " +
                std::to_string(impl.common.status) +
                ", out of memory?) for n = " + std::to_string(n));
  }
  cholmod_factorize(&view, impl.factor, &impl.common);
  const long minor = static_cast<long>(impl.factor->minor);
  if (impl.common.status == CHOLMOD_NOT_POSDEF || minor < n) {
    impl.release_factor();
    throw Error(
        "CholmodSolver::compute: the matrix is not positive definite (Cholesky broke "
        "down at pivot " +
        std::to_string(minor) + " of " + std::to_string(n) +
        ", in CHOLMOD's fill-reducing order). A pressure matrix of an all-Neumann region "
        "is only semidefinite: pin one pressure or use PcgMic0Solver.");
  }
  if (impl.common.status < CHOLMOD_OK) {
    impl.release_factor();
    throw Error("CholmodSolver::compute: CHOLMOD factorisation failed (status " +
                std::to_string(impl.common.status) + ")");
  }
}

SolveStats CholmodSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  Impl& impl = *m_impl;
  if (impl.factor == nullptr) {
    throw Error("CholmodSolver::solve: no factor; call compute(A) first (and check it succeeded)");
  }
  const long n = static_cast<long>(impl.a.rows());
  if (b.size() != n) {
    throw Error("CholmodSolver::solve: right-hand side has " + std::to_string(b.size()) +
                " entries, the matrix has " + std::to_string(n) + " rows");
  }
  SolveStats stats;
  stats.converged = true;
  const double b_norm = b.norm();
  if (b_norm == 0.0) {
    x = Eigen::VectorXd::Zero(n);
    return stats;
  }
  cholmod_dense rhs{};
  rhs.nrow = static_cast<size_t>(n);
  rhs.ncol = 1;
  rhs.nzmax = static_cast<size_t>(n);
  rhs.d = static_cast<size_t>(n);
  rhs.x = const_cast<double*>(b.data());  // read only by cholmod_solve
  rhs.z = nullptr;
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* solution = cholmod_solve(CHOLMOD_A, impl.factor, &rhs, &impl.common);
  if (solution == nullptr) {
    throw Error("CholmodSolver::solve: cholmod_solve failed (status " +
                std::to_string(impl.common.status) + ")");
  }
  x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(solution->x), n);
  cholmod_free_dense(&solution, &impl.common);
  stats.relative_residual = (b - impl.a * x).norm() / b_norm;
  return stats;
}

}  // namespace shellflow::linear
