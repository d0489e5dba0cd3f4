// Pressure-solve benchmarks (§4.3, Guendelman et al. 2005): PCG with MIC(0) (Bridson
// 2008), PCG with a multigrid V-cycle on the matrix-free operator (McAdams et al. 2010),
// and the CHOLMOD direct reference on the 7-point Poisson matrix with Dirichlet
// boundary, n^3 cells, right-hand side b = A x* (manufactured), relative tolerance 1e-5
// (the 128^3 plume target). Counters: iterations, final relative residual,
// unknowns. Setup (matrix assembly) is outside the timed region; "compute" is the
// factorisation, "solve" the iterations or triangular solves.
#include <benchmark/benchmark.h>

#include <algorithm>

#include "../unit/linear/poisson_matrix.hpp"
#include "shellflow/linear/cholmod_solver.hpp"
#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/multigrid_preconditioner.hpp"
#include "shellflow/linear/pcg_mic0_solver.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"

namespace {

using shellflow::linear::CholmodSolver;
using shellflow::linear::GridLaplacian;
using shellflow::linear::MultigridPreconditioner;
using shellflow::linear::PcgMic0Solver;
using shellflow::linear::SolveStats;
using shellflow::linear::SparseMatrix;
using namespace shellflow::linear::testing;

constexpr double kTolerance = 1e-5;

void report(benchmark::State& state, const SolveStats& stats, const SparseMatrix& a) {
  state.counters["iterations"] = stats.iterations;
  state.counters["residual"] = stats.relative_residual;
  state.counters["unknowns"] = static_cast<double>(a.rows());
}

void BM_PcgMic0Compute(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const SparseMatrix a = poisson_7point(n, Boundary::Dirichlet);
  PcgMic0Solver solver;
  for (auto _ : state) solver.compute(a);
}

void BM_PcgMic0Solve(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const SparseMatrix a = poisson_7point(n, Boundary::Dirichlet);
  const Eigen::VectorXd b = a * manufactured_solution(n);
  PcgMic0Solver solver;
  solver.compute(a);
  SolveStats stats;
  for (auto _ : state) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
    stats = solver.solve(b, x, kTolerance, 10000);
    benchmark::DoNotOptimize(x.data());
  }
  report(state, stats, a);
}

/// The Dirichlet 7-point Laplacian of poisson_7point() as a matrix-free GridLaplacian.
GridLaplacian dirichlet_laplacian(int n) {
  GridLaplacian a(Eigen::Vector3i(n, n, n));
  for (int axis = 0; axis < 3; ++axis)
    std::fill(a.weights(axis).begin(), a.weights(axis).end(), 1.0);
  return a;
}

/// The same operator every time: after the first build compute() keeps the hierarchy, so
/// this times the fingerprint check of an unchanged smoke box (BM_MultigridComputeWithSheet
/// times a rebuild).
void BM_MultigridCompute(benchmark::State& state) {
  const GridLaplacian a = dirichlet_laplacian(static_cast<int>(state.range(0)));
  MultigridPreconditioner mg;
  for (auto _ : state) mg.compute(a);
  state.counters["levels"] = mg.levels();
}

/// A hierarchy rebuilt every step, as under a moving shell: the plate moves by a cell
/// between builds (the same faces twice would reuse the hierarchy).
void BM_MultigridComputeWithSheet(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  // The Dirichlet box cut by a tilted plate that closes the faces it crosses.
  GridLaplacian plates[2] = {dirichlet_laplacian(n), dirichlet_laplacian(n)};
  for (int lift = 0; lift < 2; ++lift) add_tilted_plate(plates[lift], n, 0.0f, lift);
  MultigridPreconditioner mg;
  int step = 0;
  for (auto _ : state) mg.compute(plates[step++ % 2]);
  state.counters["levels"] = mg.levels();
}

void BM_MultigridPcgSolve(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const GridLaplacian a = dirichlet_laplacian(n);
  const Eigen::VectorXd x_star = manufactured_solution(n);
  Eigen::VectorXd b(x_star.size());
  a.multiply_and_dot(x_star, b);
  MultigridPreconditioner mg;
  mg.compute(a);
  SolveStats stats;
  for (auto _ : state) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
    stats = shellflow::linear::preconditioned_cg(a, mg, b, x, kTolerance, 10000);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["iterations"] = stats.iterations;
  state.counters["residual"] = stats.relative_residual;
  state.counters["unknowns"] = static_cast<double>(a.size());
}

void BM_MultigridVCycle(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const GridLaplacian a = dirichlet_laplacian(n);
  MultigridPreconditioner mg;
  mg.compute(a);
  const Eigen::VectorXd r = manufactured_solution(n);
  Eigen::VectorXd z;
  for (auto _ : state) {
    mg.apply(r, z);
    benchmark::DoNotOptimize(z.data());
  }
}

void BM_CholmodCompute(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const SparseMatrix a = poisson_7point(n, Boundary::Dirichlet);
  CholmodSolver solver;
  for (auto _ : state) solver.compute(a);
}

void BM_CholmodSolve(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const SparseMatrix a = poisson_7point(n, Boundary::Dirichlet);
  const Eigen::VectorXd b = a * manufactured_solution(n);
  CholmodSolver solver;
  solver.compute(a);
  SolveStats stats;
  Eigen::VectorXd x;
  for (auto _ : state) {
    stats = solver.solve(b, x);
    benchmark::DoNotOptimize(x.data());
  }
  report(state, stats, a);
}

}  // namespace

BENCHMARK(BM_PcgMic0Compute)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PcgMic0Solve)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MultigridCompute)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MultigridComputeWithSheet)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MultigridPcgSolve)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MultigridVCycle)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CholmodCompute)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CholmodSolve)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
