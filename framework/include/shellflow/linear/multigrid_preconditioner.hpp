#pragma once
// MultigridPreconditioner: one geometric multigrid V-cycle on the cell grid of a
// GridLaplacian as the preconditioner of CG — McAdams, Sifakis & Teran, "A parallel
// multigrid Poisson solver for fluids simulation on large grids", SCA 2010 — for the
// pressure equation of the MAC-grid projection (§4.3, Guendelman et al. 2005).
//
//  - Levels: cells halved per axis (ceil(n/2)) while every axis has >= 8 cells, so the
//    coarsest grid has 4–7 cells on its shortest axis.
//  - Coarse operators by rediscretisation from the faces: a coarse face's weight is half
//    the sum of the (up to four) fine face weights it covers. This is the coarse face
//    mask of McAdams et al. generalised to fractional openness: a face half closed by a
//    shell couples half as strongly, a Dirichlet (open) domain face stays Dirichlet, and
//    the factor 1/2 is the Galerkin scale P^T A_h P ≈ 2 A_{2h} of the unit 7-point
//    Laplacian under trilinear interpolation with restriction P^T.
//  - Transfers: trilinear prolongation P between cell centres (3/4, 1/4 per axis,
//    constant extrapolation at the domain boundary) and restriction exactly P^T. Along an
//    axis where the face between a cell and its far parent's side is closed, the cell
//    takes its near parent alone: no correction crosses a shell. That keeps the count flat
//    where shells lie on coarse faces (a shell-cut 64^3 box: 33 -> 11 iterations); a sheet
//    through coarse cells still mixes its two sides in them (a curtain: -12%).
//  - Smoother: red–black Gauss–Seidel, `smoothing_sweeps` forward (red, black) before
//    the coarse correction and as many backward (black, red) after; the coarsest grid
//    gets `coarsest_sweeps` symmetric sweeps (red, black, red) from zero. Cells whose
//    faces all have weight 0 (isolated by shells) are left at 0.
// With the post-smoother the adjoint of the pre-smoother, R = P^T and symmetric coarse
// operators, the V-cycle is a symmetric positive (semi)definite operator, so CG stays
// valid (tests check <x, M^{-1} y> = <M^{-1} x, y>). It runs in single precision (the
// preconditioner only needs a few digits; CG itself stays in double), every sweep with
// OpenMP over (k, j) rows. Not thread safe: apply() works in the levels' buffers.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/preconditioner.hpp"

namespace shellflow::linear {

struct MultigridSettings {
  /// Red–black Gauss–Seidel sweeps before and after each coarse correction.
  int smoothing_sweeps = 2;
  /// Symmetric sweeps on the coarsest grid.
  int coarsest_sweeps = 30;
};

class MultigridPreconditioner final : public Preconditioner {
 public:
  /// Throws shellflow::Error for sweeps < 1.
  explicit MultigridPreconditioner(MultigridSettings settings = {});

  /// Builds the level hierarchy of A (weights copied; buffers reused when the grid size
  /// does not change between calls).
  void compute(const GridLaplacian& A);

  int size() const override { return m_levels.empty() ? 0 : m_levels[0].cells.prod(); }
  /// z = V-cycle(r) from a zero initial guess.
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

  /// Number of levels (fine grid included).
  int levels() const { return static_cast<int>(m_levels.size()); }
  const MultigridSettings& settings() const { return m_settings; }

  /// One level of the hierarchy (public for the implementation's helpers).
  struct Level {
    Eigen::Vector3i cells = Eigen::Vector3i::Zero();
    std::array<std::vector<float>, 3> weight;  ///< face weights, GridLaplacian layout
    /// With unit_weights (every weight 0 or 1, as on the projection's fine grid) the
    /// weights are kept as bytes in `open` instead (less memory traffic per sweep).
    bool unit_weights = false;
    std::array<std::vector<std::uint8_t>, 3> open;
    std::vector<float> dirichlet;         ///< per-cell Dirichlet conductance (empty: none)
    std::vector<float> inverse_diagonal;  ///< 1 / A_cc, 0 for an isolated cell
    /// Per cell, bit d: its face towards its far coarse parent along axis d is closed, so
    /// the transfers to the next level skip that parent (no correction across a shell).
    std::vector<std::uint8_t> near_only;
    std::vector<std::uint8_t> row_near_only;  ///< per row (j, k): any cell with a bit set
    mutable std::vector<float> x, b, r;   ///< iterate, right-hand side, residual
  };

 private:
  MultigridSettings m_settings;
  std::vector<Level> m_levels;
};

}  // namespace shellflow::linear
