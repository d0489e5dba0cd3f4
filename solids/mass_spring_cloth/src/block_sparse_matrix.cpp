#include "mass_spring_cloth/block_sparse_matrix.hpp"

#include <algorithm>

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
}

int BlockSparseMatrix::find(int i, int j) const {
  const auto begin = m_columns.begin() + m_row_start[i],
             end = m_columns.begin() + m_row_start[i + 1];
  const auto found = std::lower_bound(begin, end, j);
  SHELLFLOW_ASSERT(found != end && *found == j);
  return static_cast<int>(found - m_columns.begin());
}

double BlockSparseMatrix::multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int n = node_count();
  const double* xp = x.data();
  double* yp = y.data();
  const double* values = m_values.data();
  double dot = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : dot) if (n >= kParallelRows)
  for (int i = 0; i < n; ++i) {
    double y0 = 0.0, y1 = 0.0, y2 = 0.0;
    for (int b = m_row_start[i]; b < m_row_start[i + 1]; ++b) {
      const double* v = values + 9 * b;
      const double* xj = xp + 3 * m_columns[b];
      y0 += v[0] * xj[0] + v[1] * xj[1] + v[2] * xj[2];
      y1 += v[3] * xj[0] + v[4] * xj[1] + v[5] * xj[2];
      y2 += v[6] * xj[0] + v[7] * xj[1] + v[8] * xj[2];
    }
    yp[3 * i] = y0, yp[3 * i + 1] = y1, yp[3 * i + 2] = y2;
    dot += xp[3 * i] * y0 + xp[3 * i + 1] * y1 + xp[3 * i + 2] * y2;
  }
  return dot;
}

double BlockSparseMatrix::residual(const Eigen::VectorXd& rhs, const Eigen::VectorXd& x,
                                   Eigen::VectorXd& r) const {
  const int n = node_count();
  const double* xp = x.data();
  const double* bp = rhs.data();
  double* rp = r.data();
  const double* values = m_values.data();
  double norm2 = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : norm2) if (n >= kParallelRows)
  for (int i = 0; i < n; ++i) {
    double r0 = bp[3 * i], r1 = bp[3 * i + 1], r2 = bp[3 * i + 2];
    for (int b = m_row_start[i]; b < m_row_start[i + 1]; ++b) {
      const double* v = values + 9 * b;
      const double* xj = xp + 3 * m_columns[b];
      r0 -= v[0] * xj[0] + v[1] * xj[1] + v[2] * xj[2];
      r1 -= v[3] * xj[0] + v[4] * xj[1] + v[5] * xj[2];
      r2 -= v[6] * xj[0] + v[7] * xj[1] + v[8] * xj[2];
    }
    rp[3 * i] = r0, rp[3 * i + 1] = r1, rp[3 * i + 2] = r2;
    norm2 += r0 * r0 + r1 * r1 + r2 * r2;
  }
  return norm2;
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
