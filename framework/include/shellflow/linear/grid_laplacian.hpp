#pragma once
// GridLaplacian: the cell-centred 7-point pressure operator of the MAC-grid projection
// (§4.3, Guendelman et al. 2005) without assembling a matrix. Every face of the grid
// carries a weight w >= 0 (its conductance):
//   - a face between two cells couples them: A_cc += w, A_cn = −w (w = 0: a Neumann face,
//     e.g. closed by a thin shell);
//   - a face on the domain boundary couples its cell to p = 0 outside (Dirichlet, open
//     face: A_cc += w) or to nothing (w = 0: wall or inflow).
// So (A x)_c = Σ_faces w_f (x_c − x_nb(f)) + d_c x_c, with x_nb = 0 outside the domain and
// d_c >= 0 an optional per-cell Dirichlet conductance: the coupling of cell c to p = 0
// beyond interior faces, as a free surface gives it (§4.3 air cells; with the ghost fluid
// method of Gibou et al. 2002, 1/θ per face crossing the surface). Cells and
// faces use the flat layout of grid::UniformGrid (x fastest): cell i + nx (j + ny k);
// faces of family a have counts cells + e_a, flat i + ni (j + nj k).
// Cut cells (docs/cut-cells.md §2.3–2.4): a cell a shell cuts into parts keeps its largest
// part in its slot and adds the others as extra unknowns, numbered after the cells. An extra
// couples only through links (w between two unknowns that no structured face joins), which
// add to both rows as a face does: A_uu += w, A_uv = −w.
// The products run with OpenMP over (k, j) rows.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/linear/linear_operator.hpp"
#include "shellflow/linear/sparse_matrix.hpp"

namespace shellflow::linear {

/// A coupling of weight w between unknowns a and b that no structured face joins.
struct Link {
  int a = 0, b = 0;
  float w = 0.0f;
};

class GridLaplacian final : public LinearOperator {
 public:
  GridLaplacian() = default;
  /// `cells` per axis (each >= 1); every face weight starts at 0.
  explicit GridLaplacian(const Eigen::Vector3i& cells);

  const Eigen::Vector3i& cells() const { return m_cells; }
  /// Face counts of family `axis`: cells + e_axis.
  Eigen::Vector3i face_counts(int axis) const;
  /// Weights of the faces of family `axis` (see the layout above), in single precision:
  /// a conductance needs no more digits than the solve's tolerance (1e-5), the
  /// projection's are 0 or 1 exactly, and floats halve the products' largest stream.
  std::vector<float>& weights(int axis) { return m_weight[axis]; }
  const std::vector<float>& weights(int axis) const { return m_weight[axis]; }
  /// Per-unknown Dirichlet conductances d_u (empty: none; else one per unknown, size()).
  std::vector<double>& dirichlet() { return m_dirichlet; }
  const std::vector<double>& dirichlet() const { return m_dirichlet; }
  /// A_uu: the sum of unknown u's face and link weights and its Dirichlet conductance.
  double diagonal(int u) const;

  /// Sets the extra unknowns (`extra_cell[e]`: the cell of unknown cells + e) and the links,
  /// replacing earlier ones; extras are numbered in cell order. Throws shellflow::Error for
  /// a cell out of range or out of order, a link of an unknown to itself or out of range, or
  /// a negative or non-finite weight. Dirichlet conductances, if any, must then be resized.
  void set_parts(std::vector<int> extra_cell, std::span<const Link> links);
  int extras() const { return static_cast<int>(m_extra_cell.size()); }
  std::span<const int> extra_cells() const { return m_extra_cell; }
  /// The links of every unknown, both directions, as compressed rows over size() unknowns
  /// (empty when there are none): unknown u's are [link_start[u], link_start[u + 1]).
  std::span<const int> link_start() const { return m_link_start; }
  std::span<const int> link_to() const { return m_link_to; }
  std::span<const float> link_weight() const { return m_link_weight; }
  bool has_links() const { return !m_link_to.empty(); }

  int size() const override { return m_cells.prod() + extras(); }
  double multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
  double residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                  Eigen::VectorXd& r) const override;

  /// The same operator as a compressed row matrix, rows filled directly in unknown order
  /// (no triplets), columns sorted: for MIC(0) and CHOLMOD. Every row stores its diagonal
  /// (0 for an unknown with no open face or link).
  SparseMatrix to_sparse() const;

  /// A 64-bit hash of the operator (cells, face weights, Dirichlet conductances, extras and
  /// links, bit for bit): equal operators hash equal, so a preconditioner can tell that A did not
  /// change (a smoke scene's walls and sources, step after step). One parallel pass.
  std::uint64_t fingerprint() const;

 private:
  Eigen::Vector3i m_cells = Eigen::Vector3i::Zero();
  std::array<std::vector<float>, 3> m_weight;
  std::vector<double> m_dirichlet;
  std::vector<int> m_extra_cell;
  std::vector<int> m_link_start, m_link_to;
  std::vector<float> m_link_weight;
};

}  // namespace shellflow::linear
