#pragma once
// CutCellWater: water on cut cells, `/fluid/water/cut_cells` (issue #52, docs/cut-cells.md):
// the parts of the cells the shells cut (CellParts), the velocities of their faces'
// fragments, and each part's φ at its virtual node (its cell's centre) for the projection on
// parts. The parts are found again whenever the shells move, and their water and fragments'
// velocities carried to the new ones (part_water_motion.hpp).
// A part's φ (docs/cut-cells.md, "Where it stands"): a slot's is the level set's sample at the
// centre it holds; an extra part's is the level set continued linearly to the centre from the
// whole cells and slots its fragments reach (a pocket between shells: from the extra parts
// beside it). Water the level set shows as air with no liquid beside the part on its side is a
// film it lost: liquid, its φ from the plane parallel to its shell that holds its water.

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/mac/face_node_transfer.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/mac/shell_pieces.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/volume_fraction.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::grid_fluid {

class CutCellWater {
 public:
  explicit CutCellWater(const grid::UniformGrid& grid) : m_grid(grid) {}

  /// Finds the parts of the cells `geometry` (built from `shells`) cuts, with every fragment at
  /// its face's velocity in `mac`, and hands them to `fraction`: each cut cell's water is
  /// shared among its parts as `level_set`'s water lies in them (4³ samples, each given to
  /// the part it sees and wet by φ's sign as it sees φ), its total kept. Nothing to do while
  /// the shells stand where they stood. Once they moved, `previous` (the shells the parts were
  /// found for) must be given: each part's water goes to the new parts (carry_part_water()),
  /// each fragment takes the velocity of the old fragment of its face with most of its corners
  /// (none: its face's), and only the cells newly cut share their water.
  void update(sdk::ShellSet shells, const ShellGeometry& geometry, const ShellGeometry* previous,
              const MacGrid& mac, const LevelSet& level_set, VolumeFraction& fraction);
  bool ready() const { return m_parts != nullptr; }
  const CellParts& parts() const { return *m_parts; }
  FragmentVelocities& fragments() { return m_fragments; }
  const FragmentVelocities& fragments() const { return m_fragments; }
  /// The split faces for §4.2's transfers.
  const CutFaces* cut_faces() { return ready() ? &m_cut_faces : nullptr; }
  /// Per part, the shells' flux out of it along each axis at the velocities `geometry` holds
  /// (shell_flux()), kept for F's dilation until the next call.
  const std::vector<Eigen::Vector3d>& shell_flux(const ShellGeometry& geometry);

  /// φ at each part's virtual node (per CellParts::parts(); see the file comment), and the
  /// parts held liquid handed to `fraction` (its dilation weights).
  const std::vector<double>& part_phi(const ShellGeometry& geometry,
                                      std::span<const double> cell_phi, VolumeFraction& fraction);
  /// After the extrapolation of the faces: the projection's fragments kept for F; a fragment
  /// whose ends' mean φ is air takes its face's velocity (those in the water keep theirs).
  void extrapolate_fragments(const MacGrid& mac, std::span<const double> cell_phi);

 private:
  /// Each cut cell's water shared among its parts as `level_set` shows it (see update()), but
  /// for the cells `before` (may be null) cut too.
  void share_water(const ShellGeometry& geometry, const LevelSet& level_set,
                   VolumeFraction& fraction, const CellParts* before) const;
  /// The fragments' velocities carried from the parts `before` (see update(); null: every
  /// fragment at its face's velocity in `mac`).
  FragmentVelocities carry_fragments(const CellParts* before, const MacGrid& mac) const;

  /// m_part_phi from the level set: a slot's sample at the centre it holds; any other part's
  /// (an extra part, a slot whose centre lies on a shell) continued to the centre from its side
  /// (see the file comment).
  void continue_level_set(std::span<const double> cell_phi);
  /// Whether each part meets a liquid neighbour on its side: across its fragments (a whole
  /// cell by `cell_phi`, a part by `liquid`) or, a slot, across its faces no shell splits.
  std::vector<std::uint8_t> liquid_beside(std::span<const double> cell_phi,
                                          std::span<const std::uint8_t> liquid) const;
  /// A film's surface in `part`: the plane parallel to its nearest shell that holds `water`
  /// (a share of the cell) against the shell, and the shell's plane, each as a height along
  /// the normal into the part, in cells from the centre; nullopt with no shell within √3Δx.
  struct FilmSurface {
    double shell = 0.0, height = 0.0;
  };
  std::optional<FilmSurface> film_surface(const ShellGeometry& geometry, const CellPart& part,
                                          double water) const;

  grid::UniformGrid m_grid;
  std::vector<sdk::Positions> m_positions;  ///< the shells the parts were found for
  std::unique_ptr<CellParts> m_parts;
  FragmentVelocities m_fragments;  ///< as the MAC's faces: extrapolated into the air
  FragmentVelocities m_projected;  ///< the projection's, which F moves with
  CutFaces m_cut_faces;
  std::vector<ShellPiece> m_pieces;
  std::vector<Eigen::Vector3d> m_shell_flux;  ///< the last projection's, per part
  std::vector<double> m_part_phi;
  /// Per part continued from neighbours that are all air: the least of their φ (else 0).
  std::vector<double> m_air_around;
};

}  // namespace shellflow::grid_fluid
