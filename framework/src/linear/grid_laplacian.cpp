#include "shellflow/linear/grid_laplacian.hpp"

#include <string>

#include "cell_stencil.hpp"
#include "parallel_threshold.hpp"
#include "shellflow/grid/fingerprint.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {

using detail::kParallelThreshold;

GridLaplacian::GridLaplacian(const Eigen::Vector3i& cells) : m_cells(cells) {
  if ((cells.array() < 1).any())
    throw Error("GridLaplacian: every axis needs at least one cell, got " +
                std::to_string(cells.x()) + " x " + std::to_string(cells.y()) + " x " +
                std::to_string(cells.z()));
  for (int a = 0; a < 3; ++a) m_weight[a].assign(face_counts(a).prod(), 0.0f);
}

Eigen::Vector3i GridLaplacian::face_counts(int axis) const {
  Eigen::Vector3i n = m_cells;
  n[axis] += 1;
  return n;
}

double GridLaplacian::diagonal(int cell) const {
  const int nx = m_cells.x(), ny = m_cells.y();
  const int i = cell % nx, j = (cell / nx) % ny, k = cell / (nx * ny);
  const auto s = detail::stencil_of(m_cells);
  const std::int64_t fx = s.face_x_row(j, k) + i;
  const std::int64_t fy = s.face_y_row(j, k) + i;
  const std::int64_t fz = s.face_z_row(j, k) + i;
  return double(m_weight[0][fx]) + m_weight[0][fx + 1] + m_weight[1][fy] + m_weight[1][fy + nx] +
         m_weight[2][fz] + m_weight[2][fz + s.plane()] +
         (m_dirichlet.empty() ? 0.0 : m_dirichlet[cell]);
}

namespace {

/// Σ over the cells of entry(cell, x_cell, (A x)_cell), the products row by row with
/// OpenMP over (k, j) rows: the one sweep behind both the product and the residual.
template <class Entry>
double sum_over_products(const detail::CellStencil& s, const std::array<std::vector<float>, 3>& w,
                         const std::vector<double>& dirichlet, const Eigen::VectorXd& x,
                         std::int64_t size, Entry&& entry) {
  const double* xp = x.data();
  const double* d = dirichlet.empty() ? nullptr : dirichlet.data();
  double total = 0.0;
#pragma omp parallel if (size >= kParallelThreshold) reduction(+ : total)
  {
    std::vector<double> sum(s.nx), diagonal(s.nx), zeros(s.nx, 0.0);
#pragma omp for collapse(2) schedule(static)
    for (int k = 0; k < s.nz; ++k)
      for (int j = 0; j < s.ny; ++j) {
        detail::row_sums(s, w[0].data(), w[1].data(), w[2].data(), xp, zeros.data(), j, k,
                         sum.data(), diagonal.data());
        const std::int64_t row = s.cell_row(j, k);
        if (d != nullptr)
          for (int i = 0; i < s.nx; ++i) diagonal[i] += d[row + i];
        for (int i = 0; i < s.nx; ++i)
          total += entry(row + i, xp[row + i], diagonal[i] * xp[row + i] - sum[i]);
      }
  }
  return total;
}

}  // namespace

double GridLaplacian::multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  double* yp = y.data();
  return sum_over_products(detail::stencil_of(m_cells), m_weight, m_dirichlet, x, size(),
                           [yp](std::int64_t c, double xc, double ax) {
                             yp[c] = ax;
                             return xc * ax;
                           });
}

double GridLaplacian::residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                               Eigen::VectorXd& r) const {
  const double* bp = b.data();
  double* rp = r.data();
  return sum_over_products(detail::stencil_of(m_cells), m_weight, m_dirichlet, x, size(),
                           [bp, rp](std::int64_t c, double, double ax) {
                             const double v = bp[c] - ax;
                             rp[c] = v;
                             return v * v;
                           });
}

SparseMatrix GridLaplacian::to_sparse() const {
  const auto s = detail::stencil_of(m_cells);
  const int n = size();
  SparseMatrix a(n, n);
  // Count, then fill each row in column order (−z, −y, −x, diagonal, +x, +y, +z).
  std::vector<int> start(n + 1, 0);
  const auto neighbours = [&](int i, int j, int k, auto&& emit) {
    const std::int64_t c = s.cell_row(j, k) + i;
    const std::int64_t fx = s.face_x_row(j, k) + i;
    const std::int64_t fy = s.face_y_row(j, k) + i;
    const std::int64_t fz = s.face_z_row(j, k) + i;
    const double d = double(m_weight[0][fx]) + m_weight[0][fx + 1] + m_weight[1][fy] +
                     m_weight[1][fy + s.nx] + m_weight[2][fz] + m_weight[2][fz + s.plane()] +
                     (m_dirichlet.empty() ? 0.0 : m_dirichlet[c]);
    if (k > 0 && m_weight[2][fz] != 0.0) emit(c - s.plane(), -m_weight[2][fz]);
    if (j > 0 && m_weight[1][fy] != 0.0) emit(c - s.nx, -m_weight[1][fy]);
    if (i > 0 && m_weight[0][fx] != 0.0) emit(c - 1, -m_weight[0][fx]);
    emit(c, d);
    if (i + 1 < s.nx && m_weight[0][fx + 1] != 0.0) emit(c + 1, -m_weight[0][fx + 1]);
    if (j + 1 < s.ny && m_weight[1][fy + s.nx] != 0.0) emit(c + s.nx, -m_weight[1][fy + s.nx]);
    if (k + 1 < s.nz && m_weight[2][fz + s.plane()] != 0.0)
      emit(c + s.plane(), -m_weight[2][fz + s.plane()]);
  };
#pragma omp parallel for collapse(2) schedule(static) if (n >= kParallelThreshold)
  for (int k = 0; k < s.nz; ++k)
    for (int j = 0; j < s.ny; ++j)
      for (int i = 0; i < s.nx; ++i) {
        int count = 0;
        neighbours(i, j, k, [&](std::int64_t, double) { ++count; });
        start[s.cell_row(j, k) + i + 1] = count;
      }
  for (int c = 0; c < n; ++c) start[c + 1] += start[c];
  a.resizeNonZeros(start[n]);
  std::copy(start.begin(), start.end(), a.outerIndexPtr());
  int* column = a.innerIndexPtr();
  double* value = a.valuePtr();
#pragma omp parallel for collapse(2) schedule(static) if (n >= kParallelThreshold)
  for (int k = 0; k < s.nz; ++k)
    for (int j = 0; j < s.ny; ++j)
      for (int i = 0; i < s.nx; ++i) {
        int p = start[s.cell_row(j, k) + i];
        neighbours(i, j, k, [&](std::int64_t col, double v) {
          column[p] = static_cast<int>(col);
          value[p] = v;
          ++p;
        });
      }
  return a;
}

std::uint64_t GridLaplacian::fingerprint() const {
  std::uint64_t h = grid::fingerprint_of(std::span<const int>(m_cells.data(), 3));
  for (int a = 0; a < 3; ++a) h = grid::fingerprint_of(std::span<const float>(m_weight[a]), h);
  return grid::fingerprint_of(std::span<const double>(m_dirichlet), h);
}

}  // namespace shellflow::linear
