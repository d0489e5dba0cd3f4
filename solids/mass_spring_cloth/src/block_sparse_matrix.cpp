#include "mass_spring_cloth/block_sparse_matrix.hpp"

#include <algorithm>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "shellflow/sdk/error.hpp"

namespace shellflow::cloth {

namespace {

// Below this many block rows the product runs serially: a parallel region costs more.
constexpr int kParallelRows = 8192;

}  // namespace

void BlockSparseMatrix::build(int node_count, const std::vector<std::pair<int, int>>& pairs) {
  std::vector<std::vector<int>> neighbours(node_count);
  for (int i = 0; i < node_count; ++i) neighbours[i].push_back(i);
  for (const auto& [i, j] : pairs) {
    neighbours[i].push_back(j);
    neighbours[j].push_back(i);
  }
  m_row_start.assign(1, 0);
  m_columns.clear();
  m_diagonal.assign(node_count, 0);
  for (int i = 0; i < node_count; ++i) {
    auto& list = neighbours[i];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (int j : list) {
      if (j == i) m_diagonal[i] = static_cast<int>(m_columns.size());
      m_columns.push_back(j);
    }
    m_row_start.push_back(static_cast<int>(m_columns.size()));
  }
  m_values.assign(9 * m_columns.size(), 0.0);
  m_scalar = Eigen::SparseMatrix<double>();
  m_scalar_source.clear();
  m_upper_start.clear();
}

int BlockSparseMatrix::find(int i, int j) const {
  const auto begin = m_columns.begin() + m_row_start[i],
             end = m_columns.begin() + m_row_start[i + 1];
  const auto found = std::lower_bound(begin, end, j);
  SHELLFLOW_ASSERT(found != end && *found == j);
  return static_cast<int>(found - m_columns.begin());
}

void BlockSparseMatrix::compress_symmetric() {
  const int n = node_count();
  if (static_cast<int>(m_upper_start.size()) != n + 1) {
    m_upper_start.assign(1, 0);
    m_upper_columns.clear();
    m_upper_source.clear();
    for (int i = 0; i < n; ++i) {
      for (int b = m_row_start[i]; b < m_row_start[i + 1]; ++b)
        if (m_columns[b] > i) {
          m_upper_columns.push_back(m_columns[b]);
          m_upper_source.push_back(b);
        }
      m_upper_start.push_back(static_cast<int>(m_upper_columns.size()));
    }
    m_upper_values.resize(9 * m_upper_columns.size());
    m_diagonal_values.resize(9 * static_cast<size_t>(n));
  }
  const int upper = static_cast<int>(m_upper_source.size());
#pragma omp parallel if (n >= kParallelRows)
  {
#pragma omp for schedule(static) nowait
    for (int k = 0; k < upper; ++k)
      std::copy_n(m_values.data() + 9 * m_upper_source[k], 9, m_upper_values.data() + 9 * k);
#pragma omp for schedule(static)
    for (int i = 0; i < n; ++i)
      std::copy_n(m_values.data() + 9 * m_diagonal[i], 9, m_diagonal_values.data() + 9 * i);
  }
}

void BlockSparseMatrix::symmetric_product(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int n = node_count();
  int threads = 1;
#ifdef _OPENMP
  if (n >= kParallelRows) threads = omp_get_max_threads();
#endif
  if (static_cast<int>(m_thread_products.size()) < threads) m_thread_products.resize(threads);
  const double* xp = x.data();
  const double* upper_values = m_upper_values.data();
  const double* diagonal_values = m_diagonal_values.data();
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
#ifdef _OPENMP
    const int thread = omp_get_thread_num();
#else
    const int thread = 0;
#endif
    Eigen::VectorXd& out = m_thread_products[thread];
    out.setZero(3 * n);
    double* yp = out.data();
    const int begin = static_cast<int>(static_cast<long>(n) * thread / threads);
    const int end = static_cast<int>(static_cast<long>(n) * (thread + 1) / threads);
    for (int i = begin; i < end; ++i) {
      const double* d = diagonal_values + 9 * i;
      const double x0 = xp[3 * i], x1 = xp[3 * i + 1], x2 = xp[3 * i + 2];
      double y0 = d[0] * x0 + d[1] * x1 + d[2] * x2;
      double y1 = d[3] * x0 + d[4] * x1 + d[5] * x2;
      double y2 = d[6] * x0 + d[7] * x1 + d[8] * x2;
      for (int k = m_upper_start[i]; k < m_upper_start[i + 1]; ++k) {
        const double* v = upper_values + 9 * k;
        const int j = m_upper_columns[k];
        const double* xj = xp + 3 * j;
        y0 += v[0] * xj[0] + v[1] * xj[1] + v[2] * xj[2];
        y1 += v[3] * xj[0] + v[4] * xj[1] + v[5] * xj[2];
        y2 += v[6] * xj[0] + v[7] * xj[1] + v[8] * xj[2];
        // Block (j, i) is the transpose of block (i, j).
        double* yj = yp + 3 * j;
        yj[0] += v[0] * x0 + v[3] * x1 + v[6] * x2;
        yj[1] += v[1] * x0 + v[4] * x1 + v[7] * x2;
        yj[2] += v[2] * x0 + v[5] * x1 + v[8] * x2;
      }
      yp[3 * i] += y0, yp[3 * i + 1] += y1, yp[3 * i + 2] += y2;
    }
  }
  y = m_thread_products[0];
  for (int t = 1; t < threads; ++t) y += m_thread_products[t];
}

double BlockSparseMatrix::multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  symmetric_product(x, y);
  return x.dot(y);
}

double BlockSparseMatrix::residual(const Eigen::VectorXd& rhs, const Eigen::VectorXd& x,
                                   Eigen::VectorXd& r) const {
  symmetric_product(x, r);
  r = rhs - r;
  return r.squaredNorm();
}

const Eigen::SparseMatrix<double>& BlockSparseMatrix::to_scalar() {
  const int n = node_count();
  if (m_scalar_source.empty()) {
    // Column-major: scalar column 3j+b holds, for every block (i, j) of the symmetric
    // pattern, rows 3i..3i+2; block (i, j) is the transpose of block (j, i) in value.
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(9 * m_columns.size());
    for (int i = 0; i < n; ++i)
      for (int b = m_row_start[i]; b < m_row_start[i + 1]; ++b)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            triplets.emplace_back(3 * i + r, 3 * m_columns[b] + c, 9.0 * b + 3 * r + c);
    m_scalar.resize(3 * n, 3 * n);
    m_scalar.setFromTriplets(triplets.begin(), triplets.end());
    m_scalar.makeCompressed();
    m_scalar_source.resize(m_scalar.nonZeros());
    for (int k = 0; k < m_scalar.nonZeros(); ++k)
      m_scalar_source[k] = static_cast<int>(m_scalar.valuePtr()[k]);
  }
  double* values = m_scalar.valuePtr();
  for (size_t k = 0; k < m_scalar_source.size(); ++k) values[k] = m_values[m_scalar_source[k]];
  return m_scalar;
}

}  // namespace shellflow::cloth
