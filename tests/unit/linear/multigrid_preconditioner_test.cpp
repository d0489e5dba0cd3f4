// MultigridPreconditioner (McAdams, Sifakis & Teran 2010) and GridLaplacian: the
// matrix-free pressure operator of the MAC-grid projection (§4.3, Guendelman et al.
// 2005) and the V-cycle preconditioned CG on the irregular domains the projection
// builds (faces closed by shells, wall and open domain faces, enclosed regions).
#include "shellflow/linear/multigrid_preconditioner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <cstdio>
#include <random>

#include "poisson_matrix.hpp"
#include "shellflow/linear/cholmod_solver.hpp"
#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/pcg_mic0_solver.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {
namespace {

using testing::Boundary;
using testing::poisson_7point;

/// Every face open (1), domain faces Dirichlet or walls.
GridLaplacian uniform(const Eigen::Vector3i& cells, Boundary boundary) {
  return testing::box_laplacian(cells, [&](int, int) { return boundary == Boundary::Dirichlet; });
}

/// The domains of the §4.3 projection, in an n x n x n box of walls with an open top:
///  - an enclosed pocket (a shell box: every face of the cell block [n/2, 3n/4)^3
///    closed), group 0;
///  - a sealed compartment x < n/4 (the x-faces at n/4 closed by a "shell", its share of
///    the open top turned into wall), group 1;
///  - a partial shell x = n/2 for y < n/2, leaving the rest connected to the open top.
/// Returns the operator and each cell's enclosed group (-1: reaches the open top).
std::pair<GridLaplacian, std::vector<int>> irregular(int n) {
  GridLaplacian a = uniform({n, n, n}, Boundary::Neumann);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i)
      testing::laplacian_face_weight(a, 1, i, n, k) = i < n / 4 ? 0.0 : 1.0;  // open top
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      testing::laplacian_face_weight(a, 0, n / 4, j, k) = 0.0;  // sealing shell
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n / 2; ++j)
      testing::laplacian_face_weight(a, 0, n / 2, j, k) = 0.0;  // partial shell
  const int lo = n / 2, hi = 3 * n / 4;
  for (int u = lo; u < hi; ++u)
    for (int v = lo; v < hi; ++v) {
      testing::laplacian_face_weight(a, 0, lo, u, v) =
          testing::laplacian_face_weight(a, 0, hi, u, v) = 0.0;
      testing::laplacian_face_weight(a, 1, u, lo, v) =
          testing::laplacian_face_weight(a, 1, u, hi, v) = 0.0;
      testing::laplacian_face_weight(a, 2, u, v, lo) =
          testing::laplacian_face_weight(a, 2, u, v, hi) = 0.0;
    }
  std::vector<int> group(n * n * n, -1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int c = i + n * (j + n * k);
        if (i < n / 4) group[c] = 1;
        if (i >= lo && i < hi && j >= lo && j < hi && k >= lo && k < hi) group[c] = 0;
      }
  return {std::move(a), std::move(group)};
}

/// A consistent right-hand side: random, each enclosed group's mean removed.
Eigen::VectorXd consistent_rhs(int size, const ConstantNullSpace& null_space, unsigned seed) {
  Eigen::VectorXd b = testing::random_vector(size, seed);
  null_space.project(b);
  return b;
}

TEST(GridLaplacian, MatchesTheAssembledSevenPointMatrix) {
  for (const Boundary boundary : {Boundary::Dirichlet, Boundary::Neumann}) {
    const int n = 7;
    const GridLaplacian a = uniform({n, n, n}, boundary);
    const SparseMatrix reference = poisson_7point(n, boundary);
    // Entries are small integers: the assembled matrices agree exactly.
    EXPECT_EQ((a.to_sparse() - reference).norm(), 0.0);
    const Eigen::VectorXd x = testing::random_vector(n * n * n, 3);
    Eigen::VectorXd y(x.size());
    const double xy = a.multiply_and_dot(x, y);
    const Eigen::VectorXd expected = reference * x;
    EXPECT_LE((y - expected).norm(), 1e-13 * expected.norm());
    EXPECT_NEAR(xy, x.dot(expected), 1e-12 * std::abs(xy));
  }
}

// R = P^T, adjoint smoothers and symmetric coarse operators make the V-cycle symmetric;
// it runs in single precision, so the two inner products agree to float round-off
// (~1e-7 relative per operation; 1e-5 leaves room for the sums over 10^4 cells).
TEST(MultigridPreconditioner, VCycleIsSymmetricPositiveDefinite) {
  for (const int n : {12, 21}) {
    auto [a, group] = irregular(n);
    MultigridPreconditioner mg;
    mg.compute(a);
    EXPECT_GE(mg.levels(), 2);
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const Eigen::VectorXd x = testing::random_vector(a.size(), seed);
      const Eigen::VectorXd y = testing::random_vector(a.size(), seed + 100);
      Eigen::VectorXd mx, my;
      mg.apply(x, mx);
      mg.apply(y, my);
      EXPECT_NEAR(x.dot(my), mx.dot(y), 1e-5 * x.norm() * my.norm()) << n << " " << seed;
      EXPECT_GT(x.dot(mx), 0.0);
      EXPECT_GT(y.dot(my), 0.0);
    }
  }
}

// The same consistent system solved three ways: MG-PCG (matrix free), MIC(0)-PCG and
// CHOLMOD (one cell of each enclosed group pinned), on a non-cubic grid with shell-closed
// faces, a sealed compartment and an enclosed pocket. Solutions agree up to a constant
// per enclosed group, to cond(A) x the 1e-10 residual (cond ~ 1e3 at this size).
TEST(MultigridPreconditioner, PcgAgreesWithMic0AndCholmodOnIrregularDomains) {
  const int n = 20;
  auto [a, group] = irregular(n);
  const ConstantNullSpace null_space(group, 2);
  const Eigen::VectorXd b = consistent_rhs(a.size(), null_space, 5);

  MultigridPreconditioner mg;
  mg.compute(a);
  Eigen::VectorXd x_mg;
  const SolveStats s_mg = preconditioned_cg(a, mg, b, x_mg, 1e-10, 500, &null_space);
  ASSERT_TRUE(s_mg.converged);

  const SparseMatrix matrix = a.to_sparse();
  PcgMic0Solver mic0;
  mic0.compute(matrix);
  Eigen::VectorXd x_mic0;
  const SolveStats s_mic0 = mic0.solve(b, x_mic0, 1e-10, 2000);
  ASSERT_TRUE(s_mic0.converged);

  SparseMatrix pinned = matrix;
  std::array<bool, 2> done{false, false};
  for (int c = 0; c < a.size(); ++c)
    if (group[c] >= 0 && !done[group[c]]) {
      pinned.coeffRef(c, c) += 1.0;
      done[group[c]] = true;
    }
  CholmodSolver direct;
  direct.compute(pinned);
  Eigen::VectorXd x_direct;
  direct.solve(b, x_direct);

  for (Eigen::VectorXd* x : {&x_mg, &x_mic0, &x_direct}) null_space.project(*x);
  std::printf("MG-PCG %d iterations, MIC(0)-PCG %d iterations\n", s_mg.iterations,
              s_mic0.iterations);
  EXPECT_LE((x_mg - x_direct).norm(), 1e-6 * x_direct.norm());
  EXPECT_LE((x_mic0 - x_direct).norm(), 1e-6 * x_direct.norm());
  EXPECT_LT(s_mg.iterations, s_mic0.iterations);
}

/// Iterations of MG-PCG and MIC(0)-PCG to a relative residual of 1e-8 on `a`.
std::pair<int, int> iterations_of(const GridLaplacian& a, const std::vector<int>& group, int groups,
                                  int* levels = nullptr) {
  const ConstantNullSpace null_space(group, groups);
  const Eigen::VectorXd b = consistent_rhs(a.size(), null_space, 9);
  MultigridPreconditioner mg;
  mg.compute(a);
  if (levels) *levels = mg.levels();
  Eigen::VectorXd x;
  const SolveStats s = preconditioned_cg(a, mg, b, x, 1e-8, 500, &null_space);
  EXPECT_TRUE(s.converged);
  PcgMic0Solver mic0;
  mic0.compute(a.to_sparse());
  Eigen::VectorXd y;
  const SolveStats s0 = mic0.solve(b, y, 1e-8, 5000);
  EXPECT_TRUE(s0.converged);
  return {s.iterations, s0.iterations};
}

// Multigrid's point: the iteration count barely grows with the grid, where MIC(0)'s grows
// like n^(1/2) (Bridson 2008, §4.3.2). Smoke box (walls, open top) from 16^3 to 64^3 (64x
// the unknowns): MG-PCG may take at most 1.5x the iterations. So on the shell-cut domain of
// irregular(), because coarse cells hold one unknown per part split by closed faces and no
// correction crosses a shell (measured: 9 / 10 / 11, issue #17 keeps these as bounds;
// 16 / 23 / 33 when the interpolation crossed shells), where MIC(0)'s triples.
TEST(MultigridPreconditioner, IterationsRoughlyIndependentOfGridSize) {
  std::vector<std::pair<int, int>> plain, cut;
  for (const int n : {16, 32, 64}) {
    GridLaplacian box = uniform({n, n, n}, Boundary::Neumann);
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < n; ++i)
        testing::laplacian_face_weight(box, 1, i, n, k) = 1.0;  // open top
    int levels = 0;
    plain.push_back(iterations_of(box, std::vector<int>(n * n * n, -1), 0, &levels));
    auto [a, group] = irregular(n);
    cut.push_back(iterations_of(a, group, 2));
    std::printf(
        "%d^3 (%d levels): smoke box MG-PCG %d, MIC(0)-PCG %d; shell-cut MG-PCG %d, "
        "MIC(0)-PCG %d iterations\n",
        n, levels, plain.back().first, plain.back().second, cut.back().first, cut.back().second);
  }
  EXPECT_LE(plain.back().first, 1.5 * plain.front().first);
  EXPECT_LE(cut.back().first, 1.5 * cut.front().first);
  const int measured[] = {9, 10, 11};
  for (int t = 0; t < 3; ++t) EXPECT_LE(cut[t].first, measured[t]) << "size " << t;
  EXPECT_GE(cut.back().second, 2.5 * cut.front().second);
}

TEST(MultigridPreconditioner, KeepsItsHierarchyOnlyWhileTheOperatorIsTheSame) {
  // compute() with an operator equal bit for bit to the last keeps the hierarchy (a smoke
  // scene rebuilds the same operator every step); any change, one face weight or one
  // Dirichlet conductance, rebuilds it, and the V-cycle is then exactly that of a fresh
  // preconditioner built from the changed operator.
  auto [a, group] = irregular(16);
  MultigridPreconditioner mg;
  mg.compute(a);
  mg.compute(a);
  EXPECT_EQ(mg.builds(), 1);
  const GridLaplacian copy = a;
  mg.compute(copy);
  EXPECT_EQ(mg.builds(), 1);

  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(a.size(), -1.0, 1.0);
  const auto same_as_fresh = [&](const GridLaplacian& changed) {
    MultigridPreconditioner fresh;
    fresh.compute(changed);
    Eigen::VectorXd z_kept, z_fresh;
    mg.apply(r, z_kept);
    fresh.apply(r, z_fresh);
    return z_kept == z_fresh;
  };
  testing::laplacian_face_weight(a, 0, 5, 6, 7) = 0.0;  // one face closed
  mg.compute(a);
  EXPECT_EQ(mg.builds(), 2);
  EXPECT_TRUE(same_as_fresh(a));
  a.dirichlet().assign(a.size(), 0.0);
  a.dirichlet()[100] = 0.5;  // one ghost-fluid conductance
  mg.compute(a);
  EXPECT_EQ(mg.builds(), 3);
  EXPECT_TRUE(same_as_fresh(a));
  a.dirichlet()[100] = 0.25;
  mg.compute(a);
  EXPECT_EQ(mg.builds(), 4);
  EXPECT_TRUE(same_as_fresh(a));
}

TEST(MultigridPreconditioner, RejectsBadSettingsAndSizes) {
  EXPECT_THROW(MultigridPreconditioner(MultigridSettings{0, 30}), Error);
  MultigridPreconditioner mg;
  Eigen::VectorXd z;
  EXPECT_THROW(mg.apply(Eigen::VectorXd::Ones(8), z), Error);  // no compute()
  EXPECT_THROW(GridLaplacian(Eigen::Vector3i(0, 4, 4)), Error);
}

}  // namespace
}  // namespace shellflow::linear

namespace shellflow::linear {
namespace {

/// A free surface (§4.3 water): cells with j >= h are air (every face touching them has
/// weight 0), each liquid cell below the surface gains the ghost-fluid conductance 1/θ
/// with θ varying along x (Gibou et al. 2002), walls elsewhere.
GridLaplacian free_surface(int n, int h) {
  GridLaplacian a = uniform({n, n, n}, Boundary::Neumann);
  a.dirichlet().assign(a.size(), 0.0);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i) {
      for (int j = h; j <= n; ++j) testing::laplacian_face_weight(a, 1, i, j, k) = 0.0;
      for (int j = h; j < n; ++j) {
        testing::laplacian_face_weight(a, 0, i, j, k) =
            testing::laplacian_face_weight(a, 0, i + 1, j, k) = 0.0;
        testing::laplacian_face_weight(a, 2, i, j, k) =
            testing::laplacian_face_weight(a, 2, i, j, k + 1) = 0.0;
      }
      const double theta = 0.05 + 0.9 * i / (n - 1.0);
      a.dirichlet()[i + n * ((h - 1) + n * k)] = 1.0 / theta;
    }
  return a;
}

// The Dirichlet conductances enter the product, the CSR form and every level of the
// V-cycle: the cycle stays symmetric positive definite on the liquid cells (float
// round-off bound as above), air cells come out 0, and MG-PCG agrees with CHOLMOD (air
// rows pinned by a unit diagonal) to cond(A) x the 1e-10 residual.
TEST(MultigridPreconditioner, FreeSurfaceDirichletCellsKeepTheCycleSymmetricAndExact) {
  const int n = 16, h = 9;
  const GridLaplacian a = free_surface(n, h);
  MultigridPreconditioner mg;
  mg.compute(a);
  Eigen::VectorXd x = testing::random_vector(a.size(), 7), y = testing::random_vector(a.size(), 8);
  for (int c = 0; c < a.size(); ++c)
    if ((c / n) % n >= h) x[c] = y[c] = 0.0;  // no residual in the air
  Eigen::VectorXd mx, my;
  mg.apply(x, mx);
  mg.apply(y, my);
  EXPECT_NEAR(x.dot(my), mx.dot(y), 1e-5 * x.norm() * my.norm());
  EXPECT_GT(x.dot(mx), 0.0);
  for (int c = 0; c < a.size(); ++c)
    if ((c / n) % n >= h) {
      EXPECT_EQ(mx[c], 0.0) << "air cell " << c;
    }

  const Eigen::VectorXd b = x;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(a.size());
  const auto stats = preconditioned_cg(a, mg, b, p, 1e-10, 200, nullptr);
  EXPECT_TRUE(stats.converged);
  SparseMatrix m = a.to_sparse();
  for (int c = 0; c < a.size(); ++c)
    if ((c / n) % n >= h) m.coeffRef(c, c) += 1.0;
  CholmodSolver direct;
  direct.compute(m);
  Eigen::VectorXd reference = Eigen::VectorXd::Zero(a.size());
  direct.solve(b, reference);
  EXPECT_LE((p - reference).lpNorm<Eigen::Infinity>(), 1e-6 * reference.lpNorm<Eigen::Infinity>());
}

// Two hierarchies that share one MultigridScratch (the projection's and the §5.1 solve's)
// give, applied in turn, exactly what each gives with its own work vectors: nothing of one
// V-cycle's buffers is read by the next. One operator has extra parts (a closed face
// through coarse cells) and a different size of coarse levels than the other.
TEST(MultigridPreconditioner, HierarchiesSharingScratchGiveTheirOwnResultsBitForBit) {
  const int n = 20;
  GridLaplacian plain = uniform({n, n, n}, Boundary::Dirichlet);
  GridLaplacian cut = uniform({n, n, n}, Boundary::Dirichlet);
  for (int k = 0; k < n; ++k)
    for (int j = 2; j < n; ++j) testing::laplacian_face_weight(cut, 0, 9, j, k) = 0.0f;
  const auto scratch = std::make_shared<MultigridScratch>();
  MultigridPreconditioner shared_plain({}, scratch), shared_cut({}, scratch);
  MultigridPreconditioner own_plain, own_cut;
  shared_plain.compute(plain);
  own_plain.compute(plain);
  shared_cut.compute(cut);
  own_cut.compute(cut);
  ASSERT_GT(shared_cut.unknowns(1), shared_plain.unknowns(1));  // the cut has extra parts
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Eigen::VectorXd r = testing::random_vector(n * n * n, seed);
    Eigen::VectorXd a, b, c, d;
    shared_cut.apply(r, a);
    shared_plain.apply(r, b);
    own_cut.apply(r, c);
    own_plain.apply(r, d);
    EXPECT_EQ(a, c) << "seed " << seed;
    EXPECT_EQ(b, d) << "seed " << seed;
  }
}

}  // namespace
}  // namespace shellflow::linear
