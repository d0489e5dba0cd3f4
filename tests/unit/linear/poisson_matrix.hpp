#pragma once
// Test matrices for the linear solvers: the 7-point finite-volume Laplacian on an
// n x n x n grid of cells (the pressure matrix of the MAC-grid projection, §4.3,
// Guendelman et al. 2005, with unit dx and density), flat index i + n (j + n k).
//   Dirichlet: p = 0 in ghost cells beyond every domain face -> diagonal 6, SPD.
//   Neumann:   zero flux through every domain face -> diagonal = number of neighbours,
//              semidefinite with the constant vector as null space.
// `face_weight(cell_a, cell_b)` > 0 scales each face coefficient (variable density).

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/multigrid_preconditioner.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"
#include "shellflow/linear/sparse_matrix.hpp"

namespace shellflow::linear::testing {

/// The weight of face (i, j, k) of family `axis` of a GridLaplacian (its flat face order).
inline float& laplacian_face_weight(GridLaplacian& a, int axis, int i, int j, int k) {
  const Eigen::Vector3i n = a.face_counts(axis);
  return a.weights(axis)[i + n.x() * (j + n.y() * k)];
}

/// `size` values uniform in [−1, 1] from `seed`.
inline Eigen::VectorXd random_vector(int size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd v(size);
  for (auto& x : v) x = u(rng);
  return v;
}

/// MG-PCG iterations to a relative residual of 1e-8 from zero on `a` (right-hand side
/// random_vector(seed 9)); a solve that does not converge in 500 fails the test.
inline int mg_pcg_iterations(const GridLaplacian& a) {
  const Eigen::VectorXd b = random_vector(a.size(), 9);
  MultigridPreconditioner mg;
  mg.compute(a);
  Eigen::VectorXd x;
  const SolveStats stats = preconditioned_cg(a, mg, b, x, 1e-8, 500, nullptr);
  EXPECT_TRUE(stats.converged);
  return stats.iterations;
}

/// A box of `cells` with every interior face open (weight 1) and each domain face open
/// (Dirichlet beyond it) where `open_side(axis, along)` says so (along: 0 or cells[axis]),
/// a wall (weight 0) elsewhere.
template <class OpenSide>
GridLaplacian box_laplacian(const Eigen::Vector3i& cells, OpenSide&& open_side) {
  GridLaplacian a(cells);
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3i n = a.face_counts(axis);
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) {
          const int along = Eigen::Vector3i(i, j, k)[axis];
          const bool domain_face = along == 0 || along == cells[axis];
          laplacian_face_weight(a, axis, i, j, k) =
              domain_face && !open_side(axis, along) ? 0.0 : 1.0;
        }
  }
  return a;
}

/// A plate tilted in x and z over the middle half of an n^3 box, its faces given weight w
/// (0: a shell closes them): a staircase of y-faces at height lift + n/3 + h(x, z) with
/// risers between columns of different height, so that no face of another weight joins
/// the cells below the plate to those above it.
inline void add_tilted_plate(GridLaplacian& a, int n, float w, int lift = 0) {
  const int lo = n / 4, hi = n - n / 4;
  const auto height = [&](int i, int k) {
    return lift + n / 3 + static_cast<int>(0.4 * (i - lo) + 0.25 * (k - lo));
  };
  for (int k = lo; k < hi; ++k)
    for (int i = lo; i < hi; ++i) {
      const int h = height(i, k);
      laplacian_face_weight(a, 1, i, h, k) = w;
      if (i + 1 < hi)  // riser between columns i and i + 1
        for (int j = std::min(h, height(i + 1, k)); j < std::max(h, height(i + 1, k)); ++j)
          laplacian_face_weight(a, 0, i + 1, j, k) = w;
      if (k + 1 < hi)
        for (int j = std::min(h, height(i, k + 1)); j < std::max(h, height(i, k + 1)); ++j)
          laplacian_face_weight(a, 2, i, j, k + 1) = w;
    }
}

enum class Boundary { Dirichlet, Neumann };

inline int cell_index(int n, int i, int j, int k) {
  return i + n * (j + n * k);
}

inline SparseMatrix poisson_7point(int n, Boundary boundary,
                                   const std::function<double(int, int)>& face_weight = {}) {
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(static_cast<size_t>(7) * n * n * n);
  const int offsets[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const int row = cell_index(n, i, j, k);
        double diagonal = 0.0;
        for (const auto& o : offsets) {
          const int a = i + o[0], b = j + o[1], c = k + o[2];
          const bool inside = a >= 0 && a < n && b >= 0 && b < n && c >= 0 && c < n;
          if (inside) {
            const int col = cell_index(n, a, b, c);
            const double w = face_weight ? face_weight(row, col) : 1.0;
            entries.emplace_back(row, col, -w);
            diagonal += w;
          } else if (boundary == Boundary::Dirichlet) {
            diagonal += 1.0;
          }
        }
        entries.emplace_back(row, row, diagonal);
      }
    }
  }
  SparseMatrix a(n * n * n, n * n * n);
  a.setFromTriplets(entries.begin(), entries.end());
  a.makeCompressed();
  return a;
}

/// Spectral condition number of the unit-weight Dirichlet matrix: eigenvalues are
/// sum over axes of 2 - 2 cos(m pi / (n + 1)), m = 1..n.
inline double dirichlet_condition_number(int n) {
  const double lo = 3.0 * (2.0 - 2.0 * std::cos(std::numbers::pi / (n + 1)));
  const double hi = 3.0 * (2.0 - 2.0 * std::cos(n * std::numbers::pi / (n + 1)));
  return hi / lo;
}

/// Effective condition number (largest over smallest nonzero eigenvalue) of the
/// unit-weight Neumann matrix: eigenvalues sum over axes of 2 - 2 cos(m pi / n), m = 0..n-1.
inline double neumann_condition_number(int n) {
  const double lo = 2.0 - 2.0 * std::cos(std::numbers::pi / n);
  const double hi = 3.0 * (2.0 - 2.0 * std::cos((n - 1) * std::numbers::pi / n));
  return hi / lo;
}

/// A smooth field plus seeded noise: the manufactured solution x*.
inline Eigen::VectorXd manufactured_solution(int n, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.5, 0.5);
  Eigen::VectorXd x(n * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double s = std::sin(2.0 * i / n) * std::cos(3.0 * j / n) + 0.3 * k / n;
        x[cell_index(n, i, j, k)] = s + noise(rng);
      }
  return x;
}

}  // namespace shellflow::linear::testing
