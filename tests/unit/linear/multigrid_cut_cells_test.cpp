// The pressure operator on cut cells (issue #52, docs/cut-cells.md §2.3–2.4): a cell that a
// level plate cuts keeps its part below the plate in its slot and adds the part above as an
// extra unknown, coupled through links. The operator must equal its assembled matrix, stay
// symmetric, and the V-cycle with the parts on its fine level must stay symmetric positive
// definite, agree with CHOLMOD through CG and cost about what the box without the plate does.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <tuple>

#include "poisson_matrix.hpp"
#include "shellflow/linear/cholmod_solver.hpp"
#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/laplacian_null_space.hpp"
#include "shellflow/linear/multigrid_preconditioner.hpp"
#include "shellflow/linear/pcg_mic0_solver.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {
namespace {

/// Walls on every side but the top and (unless `closed_bottom`) the bottom, which are open
/// (p = 0 beyond them), so that both sides of a plate across the box meet a Dirichlet boundary.
GridLaplacian open_ended_box(int n, bool closed_bottom = false) {
  return testing::box_laplacian({n, n, n}, [n, closed_bottom](int axis, int along) {
    return axis == 1 && ((along == 0 && !closed_bottom) || along == n);
  });
}

/// The box with a level plate in cell row `row`, `offset` of a cell above its centres, over
/// the cells with `lo <= i, k < hi` (the whole box for lo = 0, hi = n): each cut cell's part
/// below the plate (½ + offset of it) keeps the slot, the part above is an extra. A side face
/// between two cut cells passes ½ + offset of its square between their lower parts (the
/// structured face) and the rest between their upper parts (a link); at the plate's edge the
/// upper fragment joins the uncut neighbour; the face above a cut cell joins its upper part to
/// the cell above (a link; the structured face closes).
GridLaplacian box_with_parts(int n, int row, double offset, int lo, int hi,
                             bool closed_bottom = false) {
  GridLaplacian a = open_ended_box(n, closed_bottom);
  const auto cut = [&](int i, int k) { return i >= lo && i < hi && k >= lo && k < hi; };
  const int cells = n * n * n;
  std::vector<int> extra_cell;
  std::vector<int> extra_of(cells, -1);
  for (int k = 0; k < n; ++k)  // in cell order: x fastest
    for (int i = 0; i < n; ++i)
      if (cut(i, k)) {
        const int c = testing::cell_index(n, i, row, k);
        extra_of[c] = cells + static_cast<int>(extra_cell.size());
        extra_cell.push_back(c);
      }
  const float below = static_cast<float>(0.5 + offset), above = static_cast<float>(0.5 - offset);
  std::vector<Link> links;
  // Upper part of a cell of the row, or its slot where the cell is whole.
  const auto upper = [&](int i, int k) {
    const int c = testing::cell_index(n, i, row, k);
    return extra_of[c] >= 0 ? extra_of[c] : c;
  };
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < n; ++i) {
      if (!cut(i, k)) continue;
      // The face above: the upper part to the cell above.
      testing::laplacian_face_weight(a, 1, i, row + 1, k) = 0.0f;
      links.push_back({upper(i, k), testing::cell_index(n, i, row + 1, k), 1.0f});
      // Side faces towards +x and +z (and towards −x, −z where that neighbour is whole).
      for (const auto& [axis, di, dk] :
           {std::tuple{0, 1, 0}, std::tuple{2, 0, 1}, std::tuple{0, -1, 0}, std::tuple{2, 0, -1}}) {
        const int ni = i + di, nk = k + dk;
        if (ni < 0 || ni >= n || nk < 0 || nk >= n) continue;  // a wall
        if ((di < 0 || dk < 0) && cut(ni, nk)) continue;       // counted from there
        const int fi = di > 0 ? ni : i, fk = dk > 0 ? nk : k;
        testing::laplacian_face_weight(a, axis, fi, row, fk) = below;
        const int far = cut(ni, nk) ? upper(ni, nk) : testing::cell_index(n, ni, row, nk);
        links.push_back({upper(i, k), far, above});
      }
    }
  a.set_parts(std::move(extra_cell), links);
  return a;
}

/// A whole-box plate and one with a hole around it (the plate over the middle half).
std::vector<std::pair<std::string, GridLaplacian>> cases(int n) {
  const int row = n / 2 - 1;
  return {{"plate across the box", box_with_parts(n, row, 0.32, 0, n)},
          {"plate over the middle", box_with_parts(n, row, -0.18, n / 4, n - n / 4)}};
}

// The matrix-free product equals the assembled matrix, which is symmetric and whose diagonal
// is diagonal(): exact in double (the same float weights summed in both).
TEST(GridLaplacianParts, ProductsMatchTheAssembledSymmetricMatrix) {
  for (auto& [name, a] : cases(9)) {
    const SparseMatrix m = a.to_sparse();
    ASSERT_EQ(m.rows(), a.size()) << name;
    EXPECT_GT(a.extras(), 0) << name;
    const SparseMatrix mt = m.transpose();
    EXPECT_EQ((m - mt).norm(), 0.0) << name;
    const Eigen::VectorXd x = testing::random_vector(a.size(), 3);
    Eigen::VectorXd y(a.size()), r(a.size());
    const double dot = a.multiply_and_dot(x, y);
    const Eigen::VectorXd expected = m * x;
    EXPECT_LE((y - expected).norm(), 1e-12 * expected.norm()) << name;
    EXPECT_NEAR(dot, x.dot(expected), 1e-12 * std::abs(dot)) << name;
    const Eigen::VectorXd b = testing::random_vector(a.size(), 4);
    a.residual(b, x, r);
    EXPECT_LE((r - (b - expected)).norm(), 1e-12 * b.norm()) << name;
    for (int u = 0; u < a.size(); ++u) EXPECT_EQ(a.diagonal(u), m.coeff(u, u)) << name << " " << u;
  }
}

// The V-cycle on the fine level's parts: <x, M y> = <M x, y> to float round-off (1e-5, the
// bound of MultigridShellSides) and <x, M x> > 0; MG-PCG then agrees with CHOLMOD and with
// MIC(0)-PCG to the solves' tolerance.
TEST(MultigridCutCells, VCycleIsSymmetricAndPcgAgreesWithCholmod) {
  for (const int n : {16, 21}) {
    for (auto& [name, a] : cases(n)) {
      const std::string label = name + " at " + std::to_string(n) + "^3";
      MultigridPreconditioner mg;
      mg.compute(a);
      ASSERT_EQ(mg.size(), a.size());
      const Eigen::VectorXd x = testing::random_vector(a.size(), 21);
      const Eigen::VectorXd y = testing::random_vector(a.size(), 71);
      Eigen::VectorXd mx, my;
      mg.apply(x, mx);
      mg.apply(y, my);
      EXPECT_NEAR(x.dot(my), mx.dot(y), 1e-5 * x.norm() * my.norm()) << label;
      EXPECT_GT(x.dot(mx), 0.0) << label;

      const Eigen::VectorXd b = testing::random_vector(a.size(), 11);
      Eigen::VectorXd p;
      ASSERT_TRUE(preconditioned_cg(a, mg, b, p, 1e-10, 500, nullptr).converged) << label;
      CholmodSolver direct;
      direct.compute(a.to_sparse());
      Eigen::VectorXd reference;
      direct.solve(b, reference);
      EXPECT_LE((p - reference).norm(), 1e-6 * reference.norm()) << label;
      PcgMic0Solver mic0;
      mic0.compute(a.to_sparse());
      Eigen::VectorXd q;
      ASSERT_TRUE(mic0.solve(b, q, 1e-10, 5000).converged) << label;
      EXPECT_LE((q - reference).norm(), 1e-6 * reference.norm()) << label;
    }
  }
}

// The parts cost about what the plain box does: at most 1.25x its iterations, issue #17's
// bound for a sheet of closed faces (MultigridShellSides), at sizes where the plate cuts cells
// on three and four coarse levels.
TEST(MultigridCutCells, PartsCostAtMostAQuarterMoreIterations) {
  for (const int n : {32, 64}) {
    const int plain = testing::mg_pcg_iterations(open_ended_box(n));
    for (auto& [name, a] : cases(n)) {
      const int cut = testing::mg_pcg_iterations(a);
      std::printf("%d^3 %s: %d MG-PCG iterations (no plate: %d)\n", n, name.c_str(), cut, plain);
      EXPECT_LE(cut, 1.25 * plain) << name << " at " << n << "^3";
    }
  }
}

// The null space read from the graph: with the bottom closed, the water under a plate across
// the box is enclosed (its constant is in the null space) and the water above it, the plate's
// far parts included, reaches the open top; with the plate over the middle only, nothing is.
TEST(MultigridCutCells, TheNullSpaceIsTheConstantOfTheEnclosedSideOnly) {
  const int n = 10, row = 4;
  for (const bool across : {true, false}) {
    const GridLaplacian a = box_with_parts(n, row, 0.3, across ? 0 : 3, across ? n : 7, true);
    const ConstantNullSpace null_space = null_space_of(a);
    EXPECT_EQ(null_space.empty(), !across);
    Eigen::VectorXd ones = Eigen::VectorXd::Ones(a.size());
    null_space.project(ones);
    for (int u = 0; u < a.size(); ++u) {
      const bool above = u >= n * n * n || (u / n) % n > row;  // an extra, or a cell above
      const bool enclosed = across && !above;
      EXPECT_EQ(ones[u], enclosed ? 0.0 : 1.0)
          << "unknown " << u << (across ? ", plate across" : "");
    }
  }
}

// Extra parts with no link (the far side of a plate in the air, in a water scene) are isolated:
// the V-cycle leaves them at 0 and CG still solves the rest, as with no parts (to the solve's
// tolerance).
TEST(MultigridCutCells, ExtraPartsWithoutLinksAreLeftAlone) {
  GridLaplacian a = open_ended_box(12);
  const Eigen::VectorXd b = testing::random_vector(a.size(), 5);
  MultigridPreconditioner plain;
  plain.compute(a);
  Eigen::VectorXd expected;
  ASSERT_TRUE(preconditioned_cg(a, plain, b, expected, 1e-10, 200, nullptr).converged);
  a.set_parts({7, 100, 1000}, {});
  Eigen::VectorXd b_parts = Eigen::VectorXd::Zero(a.size());
  b_parts.head(b.size()) = b;
  MultigridPreconditioner mg;
  mg.compute(a);
  Eigen::VectorXd z;
  mg.apply(b_parts, z);
  EXPECT_EQ(z.tail(3), Eigen::Vector3d::Zero());
  Eigen::VectorXd x;
  ASSERT_TRUE(preconditioned_cg(a, mg, b_parts, x, 1e-10, 200, nullptr).converged);
  EXPECT_LE((x.head(b.size()) - expected).norm(), 1e-8 * expected.norm());
}

// A changed link weight is a new operator: the hierarchy is rebuilt.
TEST(MultigridCutCells, AChangedLinkIsANewOperator) {
  GridLaplacian a = box_with_parts(12, 5, 0.2, 0, 12);
  MultigridPreconditioner mg;
  mg.compute(a);
  mg.compute(a);
  EXPECT_EQ(mg.builds(), 1);
  std::vector<Link> links;
  for (int u = 0; u < a.size(); ++u)
    for (int l = a.link_start()[u]; l < a.link_start()[u + 1]; ++l)
      if (u < a.link_to()[l]) links.push_back({u, a.link_to()[l], a.link_weight()[l]});
  links.front().w *= 0.5f;
  a.set_parts(std::vector<int>(a.extra_cells().begin(), a.extra_cells().end()), links);
  mg.compute(a);
  EXPECT_EQ(mg.builds(), 2);
}

// Bad parts are refused with what is wrong: a cell out of range or out of order, a link out of
// range, to itself or with a bad weight; a link between two cells of one red–black colour (two
// parts of one cell, as the §5.1 solve's cloth will need) is refused by the multigrid.
TEST(MultigridCutCells, BadPartsAreRefusedNamingTheProblem) {
  GridLaplacian a = open_ended_box(8);
  const auto refusal = [&](std::vector<int> extra_cell, std::vector<Link> links) {
    try {
      a.set_parts(std::move(extra_cell), links);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refusal({512}, {}).find("outside the 512 cells"), std::string::npos);
  EXPECT_NE(refusal({5, 3}, {}).find("in cell order"), std::string::npos);
  EXPECT_NE(refusal({3}, {{512, 512, 1.0f}}).find("two different unknowns"), std::string::npos);
  EXPECT_NE(refusal({3}, {{3, 513, 1.0f}}).find("below 513"), std::string::npos);
  EXPECT_NE(refusal({3}, {{3, 512, -1.0f}}).find("finite weight >= 0"), std::string::npos);
  a.set_parts({3}, std::vector<Link>{{3, 512, 1.0f}});  // cell 3 to its own extra part
  MultigridPreconditioner mg;
  try {
    mg.compute(a);
    ADD_FAILURE() << "a link within a cell was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("one red-black colour"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace shellflow::linear
