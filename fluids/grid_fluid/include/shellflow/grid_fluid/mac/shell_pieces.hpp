#pragma once
// ShellPieces: the shells' triangles clipped into the cells they cut into parts (issue #52,
// docs/cut-cells.md §2.2, §2.4): each piece bounds the part on its normal's side and the part
// on the other. A shell that moves sweeps each part's volume at the rate its pieces' normal
// velocity gives, the flux the projection balances with the part's fragments.

#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/wedge_caster.hpp"
#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {

/// One triangle of a shell clipped to one cell that shells cut.
struct ShellPiece {
  std::int64_t cell = -1;
  double area = 0.0;                                 ///< over Δx²
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< the triangle's unit normal
  geometry::WedgeHit centroid;  ///< where the piece's centroid lies on its triangle
  /// The parts (indices into CellParts::parts()) on the normal's side and on the other; −1
  /// where that side sees none (a pocket holding no corner, a wedge).
  std::int32_t front = -1, back = -1;
};

/// The pieces of `shells` in the cells `parts` cuts, in cell order (then shell, triangle).
std::vector<ShellPiece> shell_pieces(const ShellGeometry& shells, const grid::UniformGrid& grid,
                                     const CellParts& parts);

/// Per part of `parts`, the flux of the shells' motion out of it through its pieces along each
/// axis, Σ A V_a n_a [m/s, over Δx²] with n the part's outward normal and V the shells'
/// velocity at each piece's centroid as `shells` hold it: a part's fragments carry its
/// negative when the water fills the part as the shell moves.
std::vector<Eigen::Vector3d> shell_flux(const ShellGeometry& shells,
                                        std::span<const ShellPiece> pieces, size_t part_count);

}  // namespace shellflow::grid_fluid
