#include "shellflow/linear/grid_laplacian.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

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

double GridLaplacian::diagonal(int u) const {
  const double dirichlet = m_dirichlet.empty() ? 0.0 : m_dirichlet[u];
  double d = dirichlet;
  if (u < m_cells.prod()) {
    const int nx = m_cells.x(), ny = m_cells.y();
    const int i = u % nx, j = (u / nx) % ny, k = u / (nx * ny);
    const auto s = detail::stencil_of(m_cells);
    const std::int64_t fx = s.face_x_row(j, k) + i;
    const std::int64_t fy = s.face_y_row(j, k) + i;
    const std::int64_t fz = s.face_z_row(j, k) + i;
    d = double(m_weight[0][fx]) + m_weight[0][fx + 1] + m_weight[1][fy] + m_weight[1][fy + nx] +
        m_weight[2][fz] + m_weight[2][fz + s.plane()] + dirichlet;
  }
  if (has_links())
    for (int l = m_link_start[u]; l < m_link_start[u + 1]; ++l) d += m_link_weight[l];
  return d;
}

void GridLaplacian::set_parts(std::vector<int> extra_cell, std::span<const Link> links) {
  const int cells = m_cells.prod();
  for (size_t e = 0; e < extra_cell.size(); ++e) {
    const int c = extra_cell[e];
    if (c < 0 || c >= cells)
      throw Error("GridLaplacian::set_parts: an extra part of cell " + std::to_string(c) +
                  ", outside the " + std::to_string(cells) + " cells");
    if (e > 0 && c < extra_cell[e - 1])
      throw Error("GridLaplacian::set_parts: extra parts must be numbered in cell order (cell " +
                  std::to_string(c) + " after cell " + std::to_string(extra_cell[e - 1]) + ")");
  }
  const int n = cells + static_cast<int>(extra_cell.size());
  for (const Link& link : links)
    if (link.a < 0 || link.a >= n || link.b < 0 || link.b >= n || link.a == link.b ||
        !(link.w >= 0.0f) || !std::isfinite(link.w))
      throw Error("GridLaplacian::set_parts: link (" + std::to_string(link.a) + ", " +
                  std::to_string(link.b) + ", " + std::to_string(link.w) + ") for " +
                  std::to_string(n) + " unknowns: it needs two different unknowns below " +
                  std::to_string(n) + " and a finite weight >= 0");
  m_extra_cell = std::move(extra_cell);
  m_link_start.clear();
  m_link_to.clear();
  m_link_weight.clear();
  if (links.empty()) return;
  m_link_start.assign(n + 1, 0);
  for (const Link& link : links) {
    ++m_link_start[link.a + 1];
    ++m_link_start[link.b + 1];
  }
  for (int u = 0; u < n; ++u) m_link_start[u + 1] += m_link_start[u];
  m_link_to.resize(m_link_start[n]);
  m_link_weight.resize(m_link_start[n]);
  std::vector<int> next(m_link_start.begin(), m_link_start.end() - 1);
  for (const Link& link : links) {
    m_link_to[next[link.a]] = link.b;
    m_link_weight[next[link.a]++] = link.w;
    m_link_to[next[link.b]] = link.a;
    m_link_weight[next[link.b]++] = link.w;
  }
}

namespace {

/// Σ over the unknowns of entry(u, x_u, (A x)_u), the cells' products row by row with
/// OpenMP over (k, j) rows, then the extras': the one sweep behind both the product and
/// the residual.
template <class Entry>
double sum_over_products(const GridLaplacian& a, const Eigen::VectorXd& x, Entry&& entry) {
  const auto s = detail::stencil_of(a.cells());
  const auto& w = a.weights(0);
  const double* xp = x.data();
  const double* d = a.dirichlet().empty() ? nullptr : a.dirichlet().data();
  const bool links = a.has_links();
  const auto start = a.link_start();
  const auto to = a.link_to();
  const auto weight = a.link_weight();
  // Σ w (x_u − x_v) over u's links.
  const auto link_product = [&](std::int64_t u) {
    double sum = 0.0;
    for (int l = start[u]; l < start[u + 1]; ++l) sum += double(weight[l]) * (xp[u] - xp[to[l]]);
    return sum;
  };
  const std::int64_t cells = a.cells().prod();
  double total = 0.0;
#pragma omp parallel if (a.size() >= kParallelThreshold) reduction(+ : total)
  {
    std::vector<double> sum(s.nx), diagonal(s.nx), zeros(s.nx, 0.0);
#pragma omp for collapse(2) schedule(static)
    for (int k = 0; k < s.nz; ++k)
      for (int j = 0; j < s.ny; ++j) {
        detail::row_sums(s, w.data(), a.weights(1).data(), a.weights(2).data(), xp, zeros.data(), j,
                         k, sum.data(), diagonal.data());
        const std::int64_t row = s.cell_row(j, k);
        if (d != nullptr)
          for (int i = 0; i < s.nx; ++i) diagonal[i] += d[row + i];
        for (int i = 0; i < s.nx; ++i) {
          double ax = diagonal[i] * xp[row + i] - sum[i];
          if (links) ax += link_product(row + i);
          total += entry(row + i, xp[row + i], ax);
        }
      }
#pragma omp for schedule(static)
    for (std::int64_t u = cells; u < a.size(); ++u) {
      const double ax = (d != nullptr ? d[u] * xp[u] : 0.0) + (links ? link_product(u) : 0.0);
      total += entry(u, xp[u], ax);
    }
  }
  return total;
}

}  // namespace

double GridLaplacian::multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  double* yp = y.data();
  return sum_over_products(*this, x, [yp](std::int64_t c, double xc, double ax) {
    yp[c] = ax;
    return xc * ax;
  });
}

double GridLaplacian::residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                               Eigen::VectorXd& r) const {
  const double* bp = b.data();
  double* rp = r.data();
  return sum_over_products(*this, x, [bp, rp](std::int64_t c, double, double ax) {
    const double v = bp[c] - ax;
    rp[c] = v;
    return v * v;
  });
}

SparseMatrix GridLaplacian::to_sparse() const {
  const auto s = detail::stencil_of(m_cells);
  const int cells = m_cells.prod();
  const int n = size();
  const bool links = has_links();
  SparseMatrix a(n, n);
  // Count, then fill each row in column order: a cell's (−z, −y, −x, diagonal, +x, +y, +z)
  // merged with its links (all to higher columns but those to cells before it).
  std::vector<int> start(n + 1, 0);
  const auto row_of = [&](int u, auto&& emit) {
    std::array<std::pair<int, double>, 7> entries;
    int count = 0;
    double d = diagonal(u);
    if (u < cells) {
      const int i = u % s.nx, j = (u / s.nx) % s.ny, k = u / (s.nx * s.ny);
      const std::int64_t fx = s.face_x_row(j, k) + i;
      const std::int64_t fy = s.face_y_row(j, k) + i;
      const std::int64_t fz = s.face_z_row(j, k) + i;
      const auto add = [&](bool inside, int column, float w) {
        if (inside && w != 0.0f) entries[count++] = {column, -double(w)};
      };
      add(k > 0, u - s.plane(), m_weight[2][fz]);
      add(j > 0, u - s.nx, m_weight[1][fy]);
      add(i > 0, u - 1, m_weight[0][fx]);
      entries[count++] = {u, d};
      add(i + 1 < s.nx, u + 1, m_weight[0][fx + 1]);
      add(j + 1 < s.ny, u + s.nx, m_weight[1][fy + s.nx]);
      add(k + 1 < s.nz, u + s.plane(), m_weight[2][fz + s.plane()]);
    } else {
      entries[count++] = {u, d};
    }
    if (!links || m_link_start[u] == m_link_start[u + 1]) {
      for (int e = 0; e < count; ++e) emit(entries[e].first, entries[e].second);
      return;
    }
    // Links may join an unknown more than once (two fragments of one face): summed.
    std::vector<std::pair<int, double>> merged(entries.begin(), entries.begin() + count);
    for (int l = m_link_start[u]; l < m_link_start[u + 1]; ++l)
      merged.emplace_back(m_link_to[l], -double(m_link_weight[l]));
    std::sort(merged.begin(), merged.end(),
              [](const auto& p, const auto& q) { return p.first < q.first; });
    for (size_t e = 0; e < merged.size();) {
      double v = 0.0;
      const int column = merged[e].first;
      for (; e < merged.size() && merged[e].first == column; ++e) v += merged[e].second;
      emit(column, v);
    }
  };
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
  for (int u = 0; u < n; ++u) {
    int count = 0;
    row_of(u, [&](int, double) { ++count; });
    start[u + 1] = count;
  }
  for (int u = 0; u < n; ++u) start[u + 1] += start[u];
  a.resizeNonZeros(start[n]);
  std::copy(start.begin(), start.end(), a.outerIndexPtr());
  int* column = a.innerIndexPtr();
  double* value = a.valuePtr();
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
  for (int u = 0; u < n; ++u) {
    int p = start[u];
    row_of(u, [&](int col, double v) {
      column[p] = col;
      value[p] = v;
      ++p;
    });
  }
  return a;
}

std::uint64_t GridLaplacian::fingerprint() const {
  std::uint64_t h = grid::fingerprint_of(std::span<const int>(m_cells.data(), 3));
  for (int a = 0; a < 3; ++a) h = grid::fingerprint_of(std::span<const float>(m_weight[a]), h);
  h = grid::fingerprint_of(std::span<const double>(m_dirichlet), h);
  h = grid::fingerprint_of(std::span<const int>(m_extra_cell), h);
  h = grid::fingerprint_of(std::span<const int>(m_link_to), h);
  return grid::fingerprint_of(std::span<const float>(m_link_weight), h);
}

}  // namespace shellflow::linear
