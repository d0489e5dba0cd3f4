#pragma once
// LevelSet: the water's level set (§4.4.1, Guendelman et al. 2005): φ <= 0 in the water,
// φ > 0 in the air, kept a signed distance [m] within `band` of the surface by fast
// marching and clamped to ±band beyond it (samples that far are never read: the surface,
// the pressure's liquid cells and the extrapolated velocities all lie within it).
// φ lives on the MAC grid's nodes (Layout::Nodes) or on its cell centres (Layout::Cells,
// one sample per pressure cell, as PhysBAM keeps it: docs/water-cell-centres.md). Either
// way the samples are the nodes of lattice(), one flat array in its
// UniformGrid::index(Location::Node, ...) order; for cells that lattice's nodes are the
// MAC cell centres and its flat index is the MAC cell index. Beyond the outermost cell
// centres φ continues constant (a wall's ghost cell holds its first cell's φ).

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::grid_fluid {

class LevelSet {
 public:
  enum class Layout { Nodes, Cells };

  LevelSet() = default;
  /// All air (φ = band) on the nodes or cell centres of the MAC grid `grid`; `band` [m] > 0.
  /// Cells need two cells along every axis (std::invalid_argument otherwise).
  LevelSet(const grid::UniformGrid& grid, double band, Layout layout = Layout::Nodes);

  Layout layout() const { return m_layout; }
  /// The lattice whose nodes are φ's samples (the MAC grid itself for Layout::Nodes).
  const grid::UniformGrid& grid() const { return m_grid; }
  /// The MAC grid the water lives in.
  const grid::UniformGrid& mac_grid() const { return m_mac; }
  /// The lattice whose nodes are the centres of `mac`'s cells.
  static grid::UniformGrid cell_centre_lattice(const grid::UniformGrid& mac);
  /// Where `lattice`'s nodes lie on `mac`: its nodes (the lattice is `mac`) or its cells
  /// (cell_centre_lattice(mac)), the same flat indices either way; how a ShellBand or a
  /// swept-point list on `mac` reads φ's samples. std::invalid_argument for another lattice.
  static grid::Location lattice_location(const grid::UniformGrid& lattice,
                                         const grid::UniformGrid& mac);
  /// `band`'s flags for `lattice`'s nodes, one byte per φ sample.
  static std::span<const std::uint8_t> band_flags(const geometry::ShellBand& band,
                                                  const grid::UniformGrid& lattice) {
    return band.flags(lattice_location(lattice, band.grid()));
  }
  /// `band`'s list of `lattice`'s nodes (their flat indices).
  static std::span<const std::int64_t> band_samples(const geometry::ShellBand& band,
                                                    const grid::UniformGrid& lattice) {
    return band.samples(lattice_location(lattice, band.grid()));
  }
  double band() const { return m_band; }
  std::vector<double>& phi() { return m_phi; }
  const std::vector<double>& phi() const { return m_phi; }

  /// Trilinear φ at world point p (clamped into the grid).
  double sample(const Eigen::Vector3d& p) const;
  /// φ at every cell centre (the mean of its 8 nodes: trilinear at the centre). With
  /// `walls` (the sides of the domain box that are walls, `2 * axis + max_side`), a node
  /// on a wall counts as no drier than the linear extrapolation of the two nodes inside
  /// it along the wall's normal (each normal, at an edge or corner); φ is not changed.
  /// Why: wall nodes have no normal velocity and stay stale and dry as water arrives;
  /// averaged in, they kept the wall's cells air while the faces carried water into them.
  void cell_values(std::vector<double>& out, const std::array<bool, 6>& walls = {}) const;
  /// Water volume [m^3] in the domain box: the exact volume where the piecewise-linear
  /// interpolant of φ is below zero, each lattice cell cut into six tetrahedra (marching
  /// tetrahedra's surface, to O(Δx²) the liquid mesh's). Sharp, so a film or a drop thinner
  /// than a cell counts for what it holds: a smeared Heaviside over-counts such water by up
  /// to its width. On cells, the half-cell strip between the outermost centres and the
  /// domain's faces counts with φ continued constant across it.
  double volume() const;
  /// The same within the MAC cells of `cells` (possibly empty: 0). On cells each lattice
  /// cell counts with the share of it inside the box (exact where φ is constant along the
  /// axis it is cut across: the strips at the domain's faces; O(Δx²) inside).
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
  /// Σ over nodes of |H(−φ) − H(−φ_other)| Δx^3 with the smeared Heaviside of width
  /// 1.5Δx (Osher and Fedkiw 2002, eq. 7.1), 1/2 per domain face a node lies on. A shape
  /// error that a change of volume alone can hide (Enright et al. 2002, §5.3's area loss
  /// counts water lost and gained alike).
  double symmetric_difference(const std::vector<double>& other) const;
  /// Nodes with φ <= 0.
  std::int64_t liquid_nodes() const;

 private:
  /// The trapezoidal rule's weight of a sample: 1/2 per face of the domain a node lies on;
  /// 1 for a cell centre.
  double node_weight(std::int64_t node) const;
  /// volume(cells) on Layout::Cells.
  double cell_centred_volume(const grid::IndexBox& cells) const;

  Layout m_layout = Layout::Nodes;
  grid::UniformGrid m_mac;
  grid::UniformGrid m_grid;
  double m_band = 0.0;
  std::vector<double> m_phi;
};

}  // namespace shellflow::grid_fluid
