#pragma once
// LevelSet: the water's level set (§4.4.1, Guendelman et al. 2005): φ <= 0 in the water,
// φ > 0 in the air, kept a signed distance [m] within `band` of the surface by fast
// marching and clamped to ±band beyond it (samples that far are never read: the surface,
// the pressure's liquid cells and the extrapolated velocities all lie within it).
// φ lives on the MAC grid's cell centres, one sample per pressure cell, as PhysBAM keeps it
// (docs/water-cell-centres.md). The samples are the nodes of grid(), the lattice whose nodes
// are the cell centres: one flat array in its UniformGrid::index(Location::Node, ...) order,
// which is the MAC cell index. Beyond the outermost centres φ continues constant (a wall's
// ghost cell holds its first cell's φ).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::grid_fluid {

class LevelSet {
 public:
  LevelSet() = default;
  /// All air (φ = band) on the cell centres of the MAC grid `grid`; `band` [m] > 0. Needs
  /// two cells along every axis (std::invalid_argument otherwise).
  LevelSet(const grid::UniformGrid& grid, double band);

  /// The lattice whose nodes are φ's samples, the MAC cell centres.
  const grid::UniformGrid& grid() const { return m_grid; }
  /// The MAC grid the water lives in.
  const grid::UniformGrid& mac_grid() const { return m_mac; }
  /// The lattice whose nodes are the centres of `mac`'s cells.
  static grid::UniformGrid cell_centre_lattice(const grid::UniformGrid& mac);
  /// `band`'s flags for the nodes of `lattice` (the centres of band's cells), one byte per
  /// φ sample; std::invalid_argument for another lattice.
  static std::span<const std::uint8_t> band_flags(const geometry::ShellBand& band,
                                                  const grid::UniformGrid& lattice);
  /// `band`'s list of `lattice`'s nodes (their flat indices, the cells').
  static std::span<const std::int64_t> band_samples(const geometry::ShellBand& band,
                                                    const grid::UniformGrid& lattice);
  double band() const { return m_band; }
  std::vector<double>& phi() { return m_phi; }
  const std::vector<double>& phi() const { return m_phi; }

  /// Trilinear φ at world point p (clamped into the grid).
  double sample(const Eigen::Vector3d& p) const;
  /// Water volume [m^3] in the domain box: the exact volume where the piecewise-linear
  /// interpolant of φ is below zero, each lattice cell cut into six tetrahedra (marching
  /// tetrahedra's surface, to O(Δx²) the liquid mesh's). Sharp, so a film or a drop thinner
  /// than a cell counts for what it holds: a smeared Heaviside over-counts such water by up
  /// to its width. The half-cell strip between the outermost centres and the domain's faces
  /// counts with φ continued constant across it.
  double volume() const;
  /// The same within the MAC cells of `cells` (possibly empty: 0): each lattice cell counts
  /// with the share of it inside the box (exact where φ is constant along the axis it is
  /// cut across: the strips at the domain's faces; O(Δx²) inside).
  double volume(const grid::IndexBox& cells) const;
  /// The water fraction of one cell from its corners' φ (NodeStencil's corner order), as
  /// volume() measures it.
  static double cell_fraction(const std::array<double, 8>& corner);
  /// The water fraction of one cell that a plane cuts, exact for a linear φ on each of its
  /// six tetrahedra: where the plane's signed distance `side` (at the cell's corners, in
  /// NodeStencil's corner order) is below zero φ is `phi_below`, elsewhere `phi_above`
  /// (each side's own φ, continued across the plane: a shell's two sides).
  static double two_sided_cell_fraction(const std::array<double, 8>& phi_below,
                                        const std::array<double, 8>& phi_above,
                                        const std::array<double, 8>& side);
  /// The volume where this water and `other` (φ of the same grid) differ [m^3]:
  /// Σ over cells of |H(−φ) − H(−φ_other)| Δx^3 with the smeared Heaviside of width
  /// 1.5Δx (Osher and Fedkiw 2002, eq. 7.1). A shape
  /// error that a change of volume alone can hide (Enright et al. 2002, §5.3's area loss
  /// counts water lost and gained alike).
  double symmetric_difference(const std::vector<double>& other) const;
  /// Cells with φ <= 0.
  std::int64_t liquid_cells() const;

 private:
  grid::UniformGrid m_mac;
  grid::UniformGrid m_grid;
  double m_band = 0.0;
  std::vector<double> m_phi;
};

}  // namespace shellflow::grid_fluid
