#pragma once
// Coarsening for MultigridPreconditioner that keeps a shell's two sides apart (issue #17;
// the shell closes faces, §4.3 Guendelman et al. 2005): each coarse cell, a 2x2x2 block of
// the finer level's cells, holds one unknown per connected part of the active fine unknowns
// in the block (joined by open faces or links inside it), and the coarse operator and the
// transfers are built on those parts — so on every level a correction stays on the side of
// the sheet it was computed for, where a single unknown per cell would average both sides.

#include <Eigen/Core>

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

/// Fills level.near_shell: the active unknowns (cells in flat order, each followed by its
/// extras) of the cells within `reach` cells (box distance) of a shell on this level — a
/// cell with extra parts, or an active cell one of whose interior faces is closed towards
/// an active neighbour.
void find_near_shell(MultigridPreconditioner::Level& level, int reach);

}  // namespace shellflow::linear::detail
