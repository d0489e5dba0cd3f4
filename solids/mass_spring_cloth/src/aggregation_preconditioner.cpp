#include "mass_spring_cloth/aggregation_preconditioner.hpp"

#include <algorithm>

#include "shellflow/sdk/error.hpp"

namespace shellflow::cloth {

void AggregationPreconditioner::build(const BlockSparseMatrix& a) {
  const int n = a.node_count();
  // Greedy aggregation (Vaněk et al. 1996, §4.1): a node whose neighbours are all free
  // starts an aggregate with them; the nodes left join a neighbouring aggregate.
  m_base_aggregate.assign(n, -1);
  m_aggregate_count = 0;
  for (int i = 0; i < n; ++i) {
    bool all_free = true;
    for (int b = a.row_begin(i); b < a.row_end(i) && all_free; ++b)
      all_free = m_base_aggregate[a.column(b)] < 0;
    if (!all_free) continue;
    for (int b = a.row_begin(i); b < a.row_end(i); ++b)
      m_base_aggregate[a.column(b)] = m_aggregate_count;
    ++m_aggregate_count;
  }
  for (int i = 0; i < n; ++i) {
    if (m_base_aggregate[i] >= 0) continue;
    for (int b = a.row_begin(i); b < a.row_end(i); ++b) {
      const int j = a.column(b);
      if (m_base_aggregate[j] >= 0 && m_base_aggregate[j] != m_aggregate_count) {
        m_base_aggregate[i] = m_base_aggregate[j];
        break;
      }
    }
    if (m_base_aggregate[i] < 0) m_base_aggregate[i] = m_aggregate_count++;
  }

  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < n; ++i)
    for (int b = a.row_begin(i); b < a.row_end(i); ++b) {
      const int I = m_base_aggregate[i], J = m_base_aggregate[a.column(b)];
      if (I < J) pairs.emplace_back(I, J);
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  m_coarse.build(m_aggregate_count, pairs);
  m_coarse_slot.resize(a.block_count());
  for (int i = 0; i < n; ++i)
    for (int b = a.row_begin(i); b < a.row_end(i); ++b)
      m_coarse_slot[b] = m_coarse.find(m_base_aggregate[i], m_base_aggregate[a.column(b)]);
  m_aggregate = m_base_aggregate;
  m_analysed = false;
}

void AggregationPreconditioner::compute(const BlockSparseMatrix& a,
                                        const std::vector<char>& fixed) {
  const int n = a.node_count();
  m_jacobi.compute(a);
  m_free_count.assign(m_aggregate_count, 0);
  for (int i = 0; i < n; ++i) {
    m_aggregate[i] = fixed[i] ? -1 : m_base_aggregate[i];
    if (!fixed[i]) ++m_free_count[m_base_aggregate[i]];
  }
  // P^T A P over the free nodes: block (I, J) sums the blocks (i, j), i in I, j in J.
  m_coarse.set_zero();
  for (int i = 0; i < n; ++i) {
    if (fixed[i]) continue;
    for (int b = a.row_begin(i); b < a.row_end(i); ++b)
      if (!fixed[a.column(b)]) m_coarse.block(m_coarse_slot[b]) += a.block(b);
  }
  // An aggregate with only fixed nodes has no unknowns: keep its rows nonsingular.
  for (int I = 0; I < m_aggregate_count; ++I)
    if (m_free_count[I] == 0) m_coarse.add_diagonal(m_coarse.diagonal(I), 1.0);
  const auto& coarse = m_coarse.to_scalar();
  if (!m_analysed) {
    m_factor.analyzePattern(coarse);
    m_analysed = true;
  }
  m_factor.factorize(coarse);
  if (m_factor.info() != Eigen::Success)
    throw NumericalError(
        "mass_spring_cloth: the coarse implicit system is not positive definite; lower the "
        "stiffness or the step (solver/max_substep)");
}

void AggregationPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  const int n = static_cast<int>(m_aggregate.size());
  m_jacobi.apply(r, z);
  Eigen::VectorXd coarse_r = Eigen::VectorXd::Zero(3 * m_aggregate_count);
  for (int i = 0; i < n; ++i)
    if (m_aggregate[i] >= 0) coarse_r.segment<3>(3 * m_aggregate[i]) += r.segment<3>(3 * i);
  const Eigen::VectorXd coarse_z = m_factor.solve(coarse_r);
  for (int i = 0; i < n; ++i)
    if (m_aggregate[i] >= 0) z.segment<3>(3 * i) += coarse_z.segment<3>(3 * m_aggregate[i]);
}

}  // namespace shellflow::cloth
