#pragma once
// VolumeFraction: the water fraction F ∈ [0, 1] of each MAC cell, carried beside the
// cell-centred level set and conserved (a coupled level set and volume of fluid, CLSVOF:
// Sussman and Puckett 2000). F moves in conservative form with the faces' velocities,
// directionally split with the dilation term of Weymouth and Yue 2010 (J. Comput. Phys.
// 229, "Conservative Volume-of-Fluid method for free-surface simulations on Cartesian
// grids"), so its total changes only where a face carries water out of the domain; the
// water a face carries comes from the donor cell's plane, its normal φ's gradient and its
// height F's (PLIC). φ is then moved to F's planes in the cells F cuts, so the surface the
// pressure sees keeps the water F holds. A layer thinner than half a cell on a wall lives in
// F where φ cannot show it (its cell turns air), and comes back to φ as it gathers.
// docs/water-cell-centres.md §5 says why.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"

namespace shellflow::grid_fluid {

struct VolumeFractionStats {
  double outflow = 0.0;  ///< water [m^3] carried out through open sides this step
  /// Water [m^3] the dilation term made in the emitters' cells, whose held faces push water
  /// out of them (added to the budget).
  double dilated = 0.0;
  /// Water [m^3] the dilation term made in other liquid cells: their faces' divergence, the
  /// projection's tolerance (an error, not in the budget).
  double divergence = 0.0;
  int parts = 0;  ///< the step's sweeps were split into this many
  double clipped = 0.0;  ///< water [m^3] lost (−) or made (+) keeping F in [0, 1] this step
  double excess = 0.0;  ///< water [m^3] held beyond F = 1 (converging air faces), after the step
  std::int64_t mixed_cells = 0;    ///< cells with 0 < F < 1 after the step
  std::int64_t moved_cells = 0;    ///< cells whose φ was moved to F's plane
};

class VolumeFraction {
 public:
  VolumeFraction() = default;
  /// F of every cell from φ (cell-centred) as it stands: the water below φ's interpolant.
  explicit VolumeFraction(const LevelSet& level_set);

  bool enabled() const { return !m_fraction.empty(); }
  /// The domain's open sides (−x, +x, −y, +y, −z, +z): water leaving through them is carried
  /// out and counted; none comes in through any side.
  void set_open(const std::array<bool, 6>& open) { m_open = open; }
  const std::vector<double>& values() const { return m_fraction; }
  std::vector<double>& values() { return m_fraction; }
  /// Σ F Δx³ [m^3].
  double volume() const;
  const VolumeFractionStats& stats() const { return m_stats; }

  /// F over dt with the faces `u` of the MAC grid (per axis; the projection's values next
  /// to liquid cells, so those are divergence free), the planes' normals from φ. `step`
  /// alternates the order of the sweeps (x y z, then z y x); `sources`, the cells of the
  /// emitters that are on (what the dilation term makes there is added water).
  void advect(const std::array<const std::vector<double>*, 3>& u, const LevelSet& level_set,
              double dt, std::int64_t step, const std::vector<grid::IndexBox>& sources = {});
  /// Water [m^3] raised to F = 0 since the start (what F's lower bound made).
  double clipped_total() const { return m_clipped_total; }
  void set_clipped_total(double total) { m_clipped_total = total; }
  /// Unites the shape of signed distance `distance` [m] with the water in the MAC cells of
  /// `cells` (an emitter: F = max(F, the shape's fraction)); returns the water added [m^3].
  double fill(const std::function<double(const Eigen::Vector3d&)>& distance,
              const grid::IndexBox& cells);
  /// φ at the centre of each cell F cuts set to its signed distance to F's plane there
  /// (normal from φ); a cell F holds no water in made air, one it fills made water. With
  /// `signs_only`, only the cells whose side disagrees with F's (F ≥ ½ is water): after
  /// the reinitialisation, so that the next step's liquid cells are F's.
  void correct(LevelSet& level_set, bool signs_only = false);

  /// The height d of the plane n·x = d (x from the centre of a unit cube, n a unit normal)
  /// below which the cube holds `fraction` of its volume.
  static double plane_height(const Eigen::Vector3d& normal, double fraction);
  /// The fraction of the box [lo, hi] (in the unit cube's coordinates about its centre)
  /// below the plane n·x = d.
  static double box_fraction_below(const Eigen::Vector3d& normal, double d,
                                   const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

 private:
  /// The three sweeps over dt (its Courant number at most ½), in the order `order` picks;
  /// sets m_stats' clipped, outflow, dilated and divergence for them.
  void sweeps(const std::array<const std::vector<double>*, 3>& u, const LevelSet& level_set,
              double dt, std::int64_t order);
  /// The unit normal (towards the air) at cell c: φ's gradient by central differences
  /// (one-sided at the walls), or −∇F where φ is flat there.
  Eigen::Vector3d normal_at(const LevelSet& level_set, const Eigen::Vector3i& c) const;

  grid::UniformGrid m_mac;
  std::vector<double> m_fraction;
  std::vector<std::uint8_t> m_dilating;   ///< the dilation term's cells: φ^n's liquid cells
  std::vector<std::uint8_t> m_in_source;  ///< the cells of the emitters that are on
  std::vector<Eigen::Vector3d> m_normal;  ///< the planes' normals (zero: not yet cut)
  std::vector<double> m_height;           ///< the planes' heights this pass
  std::vector<double> m_carried;          ///< the water each face carries this pass
  std::vector<double> m_corrected;        ///< correct()'s φ being built
  double m_clipped_total = 0.0;
  std::array<bool, 6> m_open{};
  VolumeFractionStats m_stats;
};

}  // namespace shellflow::grid_fluid
