#pragma once
// CellParts: the cells that thin shells cut into pieces the flow cannot join inside the cell,
// and the faces between them (issue #52, docs/cut-cells.md §2.1–2.3). A cell's parts are the
// groups of its eight corners joined by cell edges that no shell's wedge touches: the virtual
// node algorithm of Molino, Bao and Fedkiw 2004, so a part is named by corners shared with the
// neighbours and a shell through the centre changes nothing. A corner inside a wedge joins no
// part; a pocket holding no corner (a fold thinner than a cell) has no part.
// A face splits likewise into fragments (its corners joined by its four edges); each fragment
// joins the part of each cell that holds its corners. Shares of volume and area come from the
// shells' plane where one plane holds every triangle near the cell or face (exact), else from
// samples each given to the part of a corner it sees.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {

/// One part of a cell with two or more.
struct CellPart {
  std::int64_t cell = -1;
  /// Bit x + 2y + 4z set for the cell's corner at offset (x, y, z) from its lowest corner.
  std::uint8_t corners = 0;
  /// The part's share of the cell's volume.
  double volume = 0.0;
  /// The cell's centre sees a corner of this part (at most one part of a cell).
  bool holds_centre = false;
  /// The part that keeps the cell's own samples (its φ, F, pressure unknown): the one holding
  /// the centre, else the largest. The others are its extra parts.
  bool slot = false;
};

/// One fragment of an interior face that is not simply open.
struct FaceFragment {
  /// Bit s + 2t set for the face's corner at offset s along axis a + 1 and t along a + 2.
  std::uint8_t corners = 0;
  /// The fragment's share of the face's square.
  double aperture = 0.0;
  /// The parts it joins (indices into CellParts::parts()); -1 where that cell is whole.
  std::int32_t minus = -1, plus = -1;
};

/// The cells on the two sides of face `face` of family `axis`: {minus, plus}, −1 beyond the
/// domain.
std::array<std::int64_t, 2> cells_beside(const grid::UniformGrid& grid, int axis,
                                         std::int64_t face);

/// A fragment's aperture as the pressure operator holds it (GridLaplacian's weights are
/// floats): every flux through a fragment reads this number, so that the parts of a projected
/// flow balance to round-off.
inline double conductance(const FaceFragment& fragment) {
  return static_cast<float>(fragment.aperture);
}

/// An interior face that shells touch: its fragments (none: the face is closed).
struct FaceSplit {
  std::int64_t face = -1;  ///< flat index in its family (UniformGrid layout)
  std::int32_t first = 0;  ///< into CellParts::fragments(axis)
  std::int32_t count = 0;
};

/// One velocity per fragment of a CellParts' split faces, per axis in CellParts::fragments_of
/// order (all of an axis' fragments, face after face): the water's normal velocity through
/// it. A face's fragment that joins its two cells' slots is mirrored in the MAC grid's own
/// face velocity.
using FragmentVelocities = std::array<std::vector<double>, 3>;

/// The largest |velocity| of any fragment (0 for none).
double max_fragment_speed(const FragmentVelocities& fragments);

class CellParts {
 public:
  /// No shells: every cell whole, every face open.
  CellParts() = default;
  /// The parts of the cells near `shells`. `band` must hold every node within Δx + ε of a
  /// shell (the solver's band, grown by 2Δx, does).
  CellParts(const ShellGeometry& shells, const geometry::ShellBand& band);

  /// Every part of every cut cell, by cell, then by corner mask.
  std::span<const CellPart> parts() const { return m_parts; }
  /// The parts of `cell`; empty when the cell is whole.
  std::span<const CellPart> parts_of(std::int64_t cell) const;
  /// The faces of family `axis` that are not simply open, in face order.
  std::span<const FaceSplit> split_faces(int axis) const { return m_splits[axis]; }
  /// The fragments of a split face.
  std::span<const FaceFragment> fragments_of(int axis, const FaceSplit& split) const {
    return std::span<const FaceFragment>(m_fragments[axis]).subspan(split.first, split.count);
  }
  /// A velocity of 0 for every fragment.
  FragmentVelocities still_fragments() const {
    return {std::vector<double>(m_fragments[0].size(), 0.0),
            std::vector<double>(m_fragments[1].size(), 0.0),
            std::vector<double>(m_fragments[2].size(), 0.0)};
  }
  /// The fragment of a split face that holds the face's corner `corner` (bit s + 2t), or
  /// none (the corner lies in a wedge, or the face is closed).
  const FaceFragment* fragment_holding(int axis, const FaceSplit& split, int corner) const {
    for (const FaceFragment& f : fragments_of(axis, split))
      if (f.corners >> corner & 1u) return &f;
    return nullptr;
  }
  /// Whether a fragment joins its face's two cells' slot parts (the MAC face's own velocity).
  bool joins_slots(const FaceFragment& fragment) const {
    return (fragment.minus < 0 || m_parts[fragment.minus].slot) &&
           (fragment.plus < 0 || m_parts[fragment.plus].slot);
  }
  /// The largest speed at which a fragment fills the smaller of the parts it joins, |u| β / v
  /// (a whole cell's v is 1), with v no less than `smallest`: the speed F's Courant number
  /// reads, as a face's |u| for whole cells.
  double max_filling_speed(const FragmentVelocities& fragments, double smallest) const;
  /// The split face `face` of family `axis`, or none when the face is simply open.
  const FaceSplit* split(int axis, std::int64_t face) const;

  /// The part of cut cell `cell` (an index into parts()) whose nearest corner that `x` sees
  /// is its; −1 when x sees none (it lies in a wedge, or in a pocket that holds no corner).
  int part_seen_from(const ShellGeometry& shells, const grid::UniformGrid& grid, std::int64_t cell,
                     const Eigen::Vector3d& x) const;

  /// Corner offsets of a cell (bit x + 2y + 4z) and of a face of family `axis` (bit s + 2t).
  static Eigen::Vector3i cell_corner(int corner) {
    return Eigen::Vector3i(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
  }
  static Eigen::Vector3i face_corner(int axis, int corner);
  /// Where corner `corner` (bit x + 2y + 4z) of cell `cell` of `grid` lies.
  static Eigen::Vector3d corner_position(const grid::UniformGrid& grid, std::int64_t cell,
                                         int corner) {
    return grid.position(
        grid::Location::Node,
        Eigen::Vector3i(grid.coordinates(grid::Location::Cell, cell) + cell_corner(corner)));
  }

 private:
  std::vector<CellPart> m_parts;
  std::array<std::vector<FaceSplit>, 3> m_splits;
  std::array<std::vector<FaceFragment>, 3> m_fragments;
};

}  // namespace shellflow::grid_fluid
