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
// The products run with OpenMP over (k, j) rows.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/linear/linear_operator.hpp"
#include "shellflow/linear/sparse_matrix.hpp"

namespace shellflow::linear {

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
  /// Per-cell Dirichlet conductances d_c (empty: none; else one per cell).
  std::vector<double>& dirichlet() { return m_dirichlet; }
  const std::vector<double>& dirichlet() const { return m_dirichlet; }
  /// A_cc: the sum of the six face weights of cell `cell` and its Dirichlet conductance.
  double diagonal(int cell) const;

  int size() const override { return m_cells.prod(); }
  double multiply_and_dot(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;
  double residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                  Eigen::VectorXd& r) const override;

  /// The same operator as a compressed row matrix, rows filled directly in cell order
  /// (no triplets): for MIC(0) and CHOLMOD. Every row stores its diagonal (0 for a cell
  /// with six zero-weight faces).
  SparseMatrix to_sparse() const;

  /// A 64-bit hash of the operator (cells, face weights, Dirichlet conductances, bit for
  /// bit): equal operators hash equal, so a preconditioner can tell that A did not change
  /// (a smoke scene's walls and sources, step after step). One parallel pass.
  std::uint64_t fingerprint() const;

 private:
  Eigen::Vector3i m_cells = Eigen::Vector3i::Zero();
  std::array<std::vector<float>, 3> m_weight;
  std::vector<double> m_dirichlet;
};

}  // namespace shellflow::linear
