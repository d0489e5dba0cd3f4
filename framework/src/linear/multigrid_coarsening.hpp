#pragma once
// Coarsening for MultigridPreconditioner that keeps a shell's two sides apart (issue #17;
// the shell closes faces, §4.3 Guendelman et al. 2005): each coarse cell, a 2x2x2 block of
// the finer level's cells, holds one unknown per connected part of the active fine unknowns
// in the block (joined by open faces or links inside it), and the coarse operator and the
// transfers are built on those parts — so on every level a correction stays on the side of
// the sheet it was computed for, where a single unknown per cell would average both sides.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "shellflow/linear/multigrid_preconditioner.hpp"

namespace shellflow::linear::detail {

/// The two coarse parents of fine cell f along one axis under trilinear interpolation
/// between cell centres: f/2 with weight 3/4 and its neighbour on f's side with 1/4, or
/// f/2 alone (weight 1) where that neighbour lies outside the domain.
struct Parents {
  int first, second;
  float first_weight, second_weight;
};

inline Parents parents_of(int f, int coarse) {
  const int near = f / 2;
  const int far = (f % 2 == 1) ? near + 1 : near - 1;
  if (far < 0 || far >= coarse) return {near, near, 1.0f, 0.0f};
  return {near, far, 0.75f, 0.25f};
}

/// 1 / A_uu for every unknown of `level` (0 where A_uu = 0: isolated cells, air).
void compute_inverse_diagonal(MultigridPreconditioner::Level& level);

/// Builds `coarse` (its `cells` set by the caller) from `fine`, whose inverse diagonal is
/// computed: the parts of each coarse cell, their rediscretised operator (faces, links,
/// Dirichlet conductances, inverse diagonal) and fine's transfer corrections (the
/// difference between the part-aware trilinear P and the plain one on cells).
void coarsen_level(MultigridPreconditioner::Level& fine, MultigridPreconditioner::Level& coarse);

/// Calls f(wx, wy, wz) with the level's face weights: one byte per face when every weight
/// is 0 or 1 (the projection's fine grid: a third of the memory traffic of floats), floats
/// otherwise.
template <class F>
void with_weights(const MultigridPreconditioner::Level& level, F&& f) {
  if (level.unit_weights)
    f(level.open[0].data(), level.open[1].data(), level.open[2].data());
  else
    f(level.face_weight[0], level.face_weight[1], level.face_weight[2]);
}

/// Fills level.near_shell: the runs of cells within `reach` cells (box distance) of a shell
/// on this level, in flat order — a
/// cell with extra parts, a cell flagged in `carried` (empty: none), or an active cell one
/// of whose interior faces is closed towards an active neighbour.
void find_near_shell(MultigridPreconditioner::Level& level, int reach,
                     const std::vector<std::uint8_t>& carried);

/// Per cell of a level (empty when every weight is 0 or 1): 1 where an active cell has a
/// face of weight other than 0 or 1 (a two-way shell's β in the §5.1 solve) towards an
/// active neighbour. Such a weight jump fits the rediscretised coarse operator as badly as
/// a closed face does, so these cells, and the coarse cells above them on every level
/// (coarsen_flags), count as near a shell too.
std::vector<std::uint8_t> fractional_face_cells(const MultigridPreconditioner::Level& level);

/// Flags of a level's cells ORed into the cells of the next coarser level.
std::vector<std::uint8_t> coarsen_flags(const std::vector<std::uint8_t>& fine,
                                        const Eigen::Vector3i& fine_cells,
                                        const Eigen::Vector3i& coarse_cells);

}  // namespace shellflow::linear::detail
