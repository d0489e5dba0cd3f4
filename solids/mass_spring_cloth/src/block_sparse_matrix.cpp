#include "mass_spring_cloth/block_sparse_matrix.hpp"

#include <algorithm>

#include "shellflow/sdk/error.hpp"

namespace shellflow::cloth {

void BlockSparseMatrix::build(int node_count, const std::vector<std::pair<int, int>>& pairs) {
  m_node_count = node_count;
  std::vector<std::vector<int>> neighbours(node_count);
  for (int i = 0; i < node_count; ++i) neighbours[i].push_back(i);
  for (const auto& [i, j] : pairs) {
    neighbours[i].push_back(j);
    neighbours[j].push_back(i);
  }
  Eigen::VectorXi row_sizes(3 * node_count);
  for (int i = 0; i < node_count; ++i) {
    auto& list = neighbours[i];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (int a = 0; a < 3; ++a) row_sizes[3 * i + a] = 3 * static_cast<int>(list.size());
  }
  m_matrix = Matrix(3 * node_count, 3 * node_count);
  m_matrix.reserve(row_sizes);
  for (int i = 0; i < node_count; ++i)
    for (int a = 0; a < 3; ++a)
      for (int j : neighbours[i])
        for (int b = 0; b < 3; ++b) m_matrix.insert(3 * i + a, 3 * j + b) = 0.0;
  m_matrix.makeCompressed();
}

BlockSparseMatrix::Slot BlockSparseMatrix::slot(int i, int j) const {
  const int* outer = m_matrix.outerIndexPtr();
  const int* inner = m_matrix.innerIndexPtr();
  const int begin = outer[3 * i], end = outer[3 * i + 1];
  const int* found = std::lower_bound(inner + begin, inner + end, 3 * j);
  SHELLFLOW_ASSERT(found != inner + end && *found == 3 * j);
  return Slot{static_cast<int>(found - inner), end - begin};
}

}  // namespace shellflow::cloth
