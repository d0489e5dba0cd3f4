// CholmodSolver: the direct reference solve (CHOLMOD supernodal LL^T) of the pressure
// matrix (§4.3, Guendelman et al. 2005).
#include "shellflow/linear/cholmod_solver.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <utility>

#include "poisson_matrix.hpp"
#include "shellflow/linear/pcg_mic0_solver.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {
namespace {

using testing::Boundary;
using testing::dirichlet_condition_number;
using testing::manufactured_solution;
using testing::poisson_7point;

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Cholesky is backward stable: relative error <= c(n) eps cond(A). c(n) = 1e3 is a
// generous constant (measured error at 16^3: 4e-15, i.e. ~0.15 eps cond).
TEST(CholmodSolver, DirichletPoissonRecoversManufacturedSolution) {
  for (const int n : {8, 16}) {
    const SparseMatrix a = poisson_7point(n, Boundary::Dirichlet);
    const Eigen::VectorXd x_star = manufactured_solution(n);
    const Eigen::VectorXd b = a * x_star;
    CholmodSolver solver;
    solver.compute(a);
    Eigen::VectorXd x = Eigen::VectorXd::Constant(b.size(), 42.0);  // ignored on entry
    const SolveStats stats = solver.solve(b, x);
    EXPECT_TRUE(stats.converged);
    EXPECT_EQ(stats.iterations, 0);
    const double error_bound = 1e3 * kEps * dirichlet_condition_number(n);
    EXPECT_LE((x - x_star).norm() / x_star.norm(), error_bound) << n;
    // Reported residual is the true one (same round-off argument as the PCG test) and
    // at round-off level: 100 eps covers the 7-term row sums with margin.
    EXPECT_NEAR(stats.relative_residual, (b - a * x).norm() / b.norm(), 16 * kEps) << n;
    EXPECT_LE(stats.relative_residual, 100 * kEps) << n;
  }
}

// The two solvers agree: |x_pcg - x_chol| / |x_chol| <= cond(A) * tolerance.
TEST(CholmodSolver, AgreesWithPcgMic0) {
  const int n = 12;
  auto weight = [](int row, int col) { return 1.0 + 0.01 * ((row + col) % 7); };
  const SparseMatrix a = poisson_7point(n, Boundary::Dirichlet, weight);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  CholmodSolver direct;
  direct.compute(a);
  Eigen::VectorXd x_direct;
  direct.solve(b, x_direct);
  PcgMic0Solver iterative;
  iterative.compute(a);
  Eigen::VectorXd x_iterative;
  const double tolerance = 1e-11;
  ASSERT_TRUE(iterative.solve(b, x_iterative, tolerance, 500).converged);
  // Weights lie in [1, 1.06]: cond <= 1.06 x the unit-weight condition number.
  const double bound = 1.06 * dirichlet_condition_number(n) * tolerance;
  EXPECT_LE((x_iterative - x_direct).norm() / x_direct.norm(), bound);
}

// A - 3 I has eigenvalues down to about -2.5: not positive definite, a clear error.
TEST(CholmodSolver, IndefiniteMatrixIsAClearError) {
  SparseMatrix a = poisson_7point(8, Boundary::Dirichlet);
  for (int i = 0; i < a.rows(); ++i) a.coeffRef(i, i) -= 3.0;
  CholmodSolver solver;
  try {
    solver.compute(a);
    FAIL() << "an indefinite matrix must be rejected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
  }
  Eigen::VectorXd x;
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(a.rows()), x), Error);  // no factor kept
  // The solver recovers with a good matrix afterwards.
  const SparseMatrix good = poisson_7point(8, Boundary::Dirichlet);
  solver.compute(good);
  const SolveStats stats = solver.solve(Eigen::VectorXd::Ones(good.rows()), x);
  EXPECT_LE(stats.relative_residual, 100 * kEps);  // round-off, as above
}

TEST(CholmodSolver, ZeroRightHandSideMoveAndMisuse) {
  CholmodSolver solver;
  Eigen::VectorXd x;
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(8), x), Error);  // no compute()
  EXPECT_THROW(solver.compute(SparseMatrix(3, 4)), Error);
  const SparseMatrix a = poisson_7point(4, Boundary::Dirichlet);
  solver.compute(a);
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(5), x), Error);
  CholmodSolver moved = std::move(solver);
  x = Eigen::VectorXd::Ones(a.rows());
  const SolveStats stats = moved.solve(Eigen::VectorXd::Zero(a.rows()), x);
  EXPECT_TRUE(stats.converged);
  EXPECT_EQ(stats.relative_residual, 0.0);
  EXPECT_EQ(x.cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace shellflow::linear
