#pragma once
// MultigridPreconditioner: one geometric multigrid V-cycle on the cell grid of a
// GridLaplacian as the preconditioner of CG — McAdams, Sifakis & Teran, "A parallel
// multigrid Poisson solver for fluids simulation on large grids", SCA 2010 — for the
// pressure equation of the MAC-grid projection (§4.3, Guendelman et al. 2005).
//
//  - Levels: cells halved per axis (ceil(n/2)) while every axis has >= 8 cells, so the
//    coarsest grid has 4–7 cells on its shortest axis.
//  - A shell's two sides stay apart on every level: a coarse cell (a 2x2x2 block of the
//    level below) holds one unknown per connected part of its fine unknowns, parts joined
//    only by open faces (weight > 0) inside the block — recursively, so a level-2 cell cut
//    by a folded sheet holds three unknowns. The largest part keeps the cell's structured
//    slot (index = cell), the others are "extra" unknowns stored after the cells, so where
//    no shell is near a level is the plain 7-point grid of McAdams et al. (see
//    multigrid_coarsening.hpp for the construction). The fine level takes the operator's
//    own extra parts and links where it has them (cut cells, GridLaplacian::set_parts).
//  - Coarse operators rediscretised from the faces, per part: the coupling between two
//    parts of neighbouring coarse cells is half the sum of the fine face weights joining
//    their members, a part's Dirichlet conductance half the sum of its members'. This is
//    the coarse face mask of McAdams et al. generalised to fractional openness and to
//    parts; the factor 1/2 is the Galerkin scale P^T A_h P ≈ 2 A_{2h} of the unit 7-point
//    Laplacian under trilinear interpolation with restriction P^T.
//  - Transfers: trilinear prolongation P between cell centres (3/4, 1/4 per axis, constant
//    extrapolation at the domain boundary) where every fine unknown reaches its eight
//    parents through open faces; elsewhere each corner of the interpolation stencil takes
//    the part(s) of that coarse cell reached from the fine unknown inside the stencil's
//    2x2x2 fine cells, and a corner reached by no path gives its weight to the reachable
//    corners nearest to it. No correction crosses a shell. Restriction is exactly P^T.
//  - Smoother: red–black Gauss–Seidel (a part's colour is its cell's: parts only couple to
//    parts of face neighbours; compute() refuses a link between cells of one colour),
//    `smoothing_sweeps` forward (red, black) before the coarse correction and as many backward
//    (black, red) after; the coarsest grid gets `coarsest_sweeps` symmetric sweeps (red, black,
//    red) from zero. Unknowns with a zero diagonal (cells isolated by shells, air cells) are left
//    at 0.
//  - A two-way sheet's faces (weight β, neither 0 nor 1, in the §5.1 solve): the
//    coarsening reads a weak one (below 0.5) as closed and a strong one as 1; the smoother
//    keeps the true weights.
//  - Near a shell (cells with extra parts, a closed face between two active cells or,
//    carried down from the fine level, a face of weight neither 0 nor 1, and the cells
//    within `near_shell_reach` of them) each level gets `near_shell_sweeps` more
//    Gauss–Seidel sweeps in flat order after the pre-smoothing, and as many in reverse
//    order before the post-smoothing: the boundary smoothing of McAdams et al. 2010 applied
//    about a sheet, where the rediscretised coarse operator fits the fine one worst (a folded
//    pocket: 15 iterations against 11 without the sweeps, 13 with them, at 64³).
// With the post-smoother the adjoint of the pre-smoother, R = P^T and symmetric coarse
// operators, the V-cycle is a symmetric positive (semi)definite operator, so CG stays
// valid (tests check <x, M^{-1} y> = <M^{-1} x, y>). It runs in single precision (the
// preconditioner only needs a few digits; CG itself stays in double), every sweep with
// OpenMP over (k, j) rows. Not thread safe: apply() works in its scratch, which two
// hierarchies that never apply at the same time may share (MultigridScratch).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/preconditioner.hpp"

namespace shellflow::linear {

struct MultigridSettings {
  /// Red–black Gauss–Seidel sweeps before and after each coarse correction.
  int smoothing_sweeps = 2;
  /// Symmetric sweeps on the coarsest grid.
  int coarsest_sweeps = 30;
  /// Extra Gauss–Seidel sweeps over the unknowns near a shell on every level, and how many
  /// cells (box distance) about the shell's cells count as near.
  int near_shell_sweeps = 2;
  int near_shell_reach = 1;
};

/// The V-cycle's work vectors (iterate, right-hand side and residual of every level), grown
/// to the largest hierarchy that uses them: the projection's and the §5.1 solve's
/// hierarchies of one grid run one after the other and share one (25 MB at 128³).
struct MultigridScratch {
  std::vector<std::array<std::vector<float>, 3>> levels;
  /// The coarsening's per-level scratch (Level::scratch_*, coarse_part), lent to the
  /// levels while compute() builds them.
  struct Coarsening {
    std::vector<int> part, coarse_part, extra_start;
    std::vector<std::uint8_t> simple;
  };
  std::vector<Coarsening> coarsening;
};

class MultigridPreconditioner final : public Preconditioner {
 public:
  /// Throws shellflow::Error for sweeps < 1. `scratch`: shared work vectors (null: own).
  explicit MultigridPreconditioner(MultigridSettings settings = {},
                                   std::shared_ptr<MultigridScratch> scratch = nullptr);

  /// Builds the level hierarchy of A (buffers reused when the grid size does not change
  /// between calls). An A equal to the last one, bit for bit (its fingerprint), keeps the
  /// hierarchy: a smoke scene's operator is the same every step unless a shell moves, and
  /// the build costs as much as two V-cycles. Face weights all 0 or 1 are copied as bytes;
  /// others are read in place (50 MB not copied at Fig. 2's size), so A must outlive the
  /// apply() calls that follow and not change before the next compute().
  void compute(const GridLaplacian& A);
  /// How many times compute() has built a hierarchy (not counting the kept ones).
  std::int64_t builds() const { return m_builds; }

  int size() const override { return m_levels.empty() ? 0 : m_levels[0].unknowns(); }
  /// z = V-cycle(r) from a zero initial guess.
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

  /// Number of levels (fine grid included).
  int levels() const { return static_cast<int>(m_levels.size()); }
  const MultigridSettings& settings() const { return m_settings; }

  /// Unknowns on level `level` (0: the fine cells; coarser: cells plus extra parts).
  int unknowns(int level) const { return m_levels[level].unknowns(); }

  /// Sparse rows of a transfer correction: rows `row[t]` with entries
  /// [start[t], start[t + 1]) of (column, value).
  struct SparseRows {
    std::vector<int> row, start{0}, column;
    std::vector<float> value;
    void clear() {
      row.clear();
      start.assign(1, 0);
      column.clear();
      value.clear();
    }
  };

  /// One level of the hierarchy (public for the implementation's helpers). Unknowns: one
  /// per cell (flat GridLaplacian layout), then `extras` more parts of cells cut by shells.
  struct Level {
    Eigen::Vector3i cells = Eigen::Vector3i::Zero();
    std::array<std::vector<float>, 3> weight;  ///< face weights, GridLaplacian layout
    /// The float face weights the level reads: `weight`'s, or on the fine level the
    /// operator's own (GridLaplacian's floats).
    std::array<const float*, 3> face_weight{};
    /// With unit_weights (every weight 0 or 1, as on the projection's fine grid) the
    /// weights are kept as bytes in `open` instead (less memory traffic per sweep).
    bool unit_weights = false;
    std::array<std::vector<std::uint8_t>, 3> open;
    /// The fine level of a §5.1 solve: the coarsening reads a weak face (a heavy two-way
    /// sheet's β) as closed and a strong one as open (detail::coarsening_weight).
    bool clamp_for_coarsening = false;
    /// Per cell: what its diagonal holds beyond its structured faces — its Dirichlet
    /// conductance plus its links to extra parts (empty: none anywhere).
    std::vector<float> dirichlet;
    /// Per unknown, coarse levels only: the conductance to p = 0 alone (Dirichlet cells and,
    /// for extras, open domain faces); level 0 reads `dirichlet` instead.
    std::vector<float> ground;
    std::vector<float> inverse_diagonal;  ///< per unknown: 1 / A_uu, 0 where A_uu = 0

    int extras = 0;                     ///< parts beyond each cell's first
    std::vector<int> extra_cell;        ///< per extra: the cell it belongs to
    std::vector<int> cell_extra_start;  ///< per cell + 1: its extras (empty when extras == 0)
    /// Couplings that involve an extra part (the 7-point faces hold the others), both
    /// directions, CSR over all unknowns; row_has_links flags grid rows (j, k) with any.
    std::vector<int> link_start, link_to;
    std::vector<float> link_weight;
    std::vector<std::uint8_t> row_has_links;

    /// Transfer to the next coarser level, P = trilinear on the cells + correction:
    /// prolongation's correction by fine unknown, restriction's (its transpose) by coarse one.
    SparseRows prolongation_correction, restriction_correction;

    /// Iterate, right-hand side, residual: bound to the scratch by apply().
    mutable float *x = nullptr, *b = nullptr, *r = nullptr;

    /// Cells near a shell, which get extra Gauss–Seidel sweeps (see near_shell_sweeps), as
    /// runs of cells [first, last) on grid row (j, k) in flat order; each active cell is
    /// swept, then its active extra parts.
    struct NearRun {
      int j, k, first, last;
    };
    std::vector<NearRun> near_shell;

    /// Scratch of the coarsening, held only while compute() runs (MultigridScratch keeps
    /// it between builds, so that a compute() per step reuses the memory): per unknown the
    /// unknown of its part on the next coarser level (-1: inactive), part numbers within a
    /// cell, per-cell counts and offsets.
    std::vector<int> coarse_part, scratch_part, scratch_extra_start;
    std::vector<std::uint8_t> scratch_simple;

    int size() const { return cells.prod(); }
    int unknowns() const { return size() + extras; }
    bool has_links() const { return !link_to.empty(); }
  };

 private:
  /// Points the levels' x, b, r at the scratch (grown to fit first).
  void bind_scratch() const;
  /// The fine level reads A's float weights in place (see compute()).
  void point_at_weights(const GridLaplacian& A);

  MultigridSettings m_settings;
  std::shared_ptr<MultigridScratch> m_scratch;
  std::vector<Level> m_levels;
  std::uint64_t m_fingerprint = 0;  ///< of the operator the levels were built from
  bool m_built = false;
  std::int64_t m_builds = 0;
};

}  // namespace shellflow::linear
