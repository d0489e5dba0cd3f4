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
// With cut cells (issue #52, docs/cut-cells.md §2.7) each part of a cell the shells cut holds
// its own water: the slot part's in the cell's F, the extras' beside it. A split face moves
// water fragment by fragment (β u), from the upwind part at its mean fill (a thin layer along
// a shell; a whole donor cell gives its PLIC slab), each part's dilation term weighs its
// fragments' flux with its fill at the step's start, and no part gives more than it holds.
// Nothing crosses a shell: it has no fragment.

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/sdk/state_buffer.hpp"

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
  /// Σ F Δx³ [m^3] (the extra parts' water included).
  double volume() const;
  /// The water [m^3] of the cells of `cells`, their extra parts' included.
  double volume_in(const grid::IndexBox& cells) const;

  /// Cut cells: the parts of the cells shells cut, their fragments' velocities (which F moves
  /// with through split faces) and, per part, the moving shells' flux out of it along each
  /// axis (ShellPieces' shell_flux(), which a part's dilation adds to its fragments'; null or
  /// empty: still shells), all kept by the caller while set; null parts: none. The extras'
  /// water starts at none.
  void set_cut_cells(const CellParts* parts, const FragmentVelocities* velocities,
                     const std::vector<Eigen::Vector3d>* shell_flux = nullptr);
  /// Which parts the last projection held liquid (per CellParts::parts(); empty: none yet):
  /// a part's dilation term weighs its fill there only, as a cell's weighs 1 where φ <= 0,
  /// since only their faces the projection balanced.
  void set_liquid_parts(std::vector<std::uint8_t> liquid) { m_part_liquid = std::move(liquid); }
  /// F of each part of CellParts::parts() that is not its cell's slot (the slots' water is
  /// values()'); the slots' entries are unused.
  const std::vector<double>& part_values() const { return m_part_fraction; }
  std::vector<double>& part_values() { return m_part_fraction; }
  const VolumeFractionStats& stats() const { return m_stats; }

  /// Before the velocity extrapolation: the projection's values of the faces next to a
  /// liquid cell that the extrapolation rewrites (`kept[axis]`: (face, u), in face order),
  /// and the cells of the emitters whose held faces they carry. F moves with the MAC's
  /// faces as the extrapolation leaves them but for those: the projection's divergence-free
  /// faces next to the water, the extrapolated ones in the air.
  void keep_projected_faces(std::array<std::vector<std::pair<std::int64_t, double>>, 3>&& kept,
                            const std::vector<grid::IndexBox>& sources) {
    m_faces_kept = true;
    m_faces_sources = sources;
    m_kept = std::move(kept);
    for (auto& cut : m_cut) cut.clear();
  }
  /// A face a shell cuts passes F through its open share `fraction`, the rest moving with
  /// the shell (`shell_velocity`): the flux the projection's faces balance (FaceApertures).
  void cut_face(int axis, std::int64_t face, double fraction, double shell_velocity) {
    m_cut[axis].push_back({face, fraction, shell_velocity});
  }
  /// F over dt, the planes' normals from φ, with the faces kept since the last projection
  /// (before the first one, `mac`'s as they stand and the emitters `on` now); what the
  /// dilation term makes in the emitters' cells is added water. The sweeps' order
  /// alternates step by step (x y z, then z y x). `cut` (one byte per cell, may be empty):
  /// the cells a shell cuts, whose φ correct() leaves alone.
  /// `max_speed` [m/s]: no face of `mac` is faster.
  void advect(const MacGrid& mac, const LevelSet& level_set, double dt, double max_speed,
              const std::vector<grid::IndexBox>& on = {}, std::span<const std::uint8_t> cut = {});
  /// For a checkpoint: F, the faces it moves with next (whole columns, `mac`'s with the
  /// kept ones over them) and their emitters, the steps, what its lower bound raised.
  /// restore() reads `mac`'s faces restored before it.
  void save(sdk::StateWriter& out, const MacGrid& mac) const;
  void restore(sdk::StateReader& in, const MacGrid& mac);
  /// Water [m^3] raised to F = 0 since the start (what F's lower bound made).
  double clipped_total() const { return m_clipped_total; }
  /// Unites the shape of signed distance `distance` [m] with the water in the MAC cells of
  /// `cells` (an emitter: F = max(F, the shape's fraction)); returns the water added [m^3].
  double fill(const std::function<double(const Eigen::Vector3d&)>& distance,
              const grid::IndexBox& cells);
  /// φ at the centre of each cell F cuts set to its signed distance to F's plane there
  /// (normal from φ); a cell F holds no water in made air, one it fills made water. With
  /// `signs_only`, only the cells whose side disagrees with F's (F ≥ ½ is water): after
  /// the reinitialisation, so that the next step's liquid cells are F's. The cells `left`
  /// flags (one byte per cell, may be empty) keep their φ. `scratch` (any contents, left
  /// holding the old φ) is where the new one is built.
  void correct(LevelSet& level_set, std::vector<double>& scratch, bool signs_only = false,
               std::span<const std::uint8_t> left = {});
  /// F set to the planes correct() would put φ on (its inverse): the share of each cell
  /// below the plane through φ at its centre, normal to φ's gradient; built in `scratch`
  /// as correct()'s φ is.
  void fit(const LevelSet& level_set, std::vector<double>& scratch);

  /// The height d of the plane n·x = d (x from the centre of a unit cube, n a unit normal)
  /// below which the cube holds `fraction` of its volume.
  static double plane_height(const Eigen::Vector3d& normal, double fraction);
  /// The fraction of the box [lo, hi] (in the unit cube's coordinates about its centre)
  /// below the plane n·x = d.
  static double box_fraction_below(const Eigen::Vector3d& normal, double d,
                                   const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

 private:
  /// Each cell with parts and its whole water (slot and far parts), in cell order.
  std::vector<std::pair<std::int64_t, double>> cells_whole_water() const;
  /// The faces along `axis` whose velocity F moves with differs from `mac`'s: the kept ones,
  /// with the cut faces' shares over them, as (face, velocity) in face order.
  std::vector<std::pair<std::int64_t, double>> moved_faces(int axis, const MacGrid& mac) const;
  /// The faces along `axis` that F moves with: `mac`'s with moved_faces() over them (a
  /// checkpoint's whole columns).
  void faces_along(int axis, const MacGrid& mac, std::vector<double>& out) const;
  /// The faces F moves with that differ from `mac`'s, per axis by line of cells
  /// (m_line_faces, m_line_start): what the sweeps read over `mac`'s own.
  void gather_line_faces(const MacGrid& mac);
  /// Gives `cell` (cut by F now) a plane, its normal found at the next pass.
  void add_plane(std::int64_t cell);
  /// The three sweeps over dt (its Courant number at most ½), in the order `order` picks;
  /// sets m_stats' clipped, outflow, dilated and divergence for them. `sources`: the cells of
  /// the emitters whose held faces the faces carry (their dilation is added water).
  void sweeps(const MacGrid& mac, const LevelSet& level_set, std::span<const std::uint8_t> cut,
              const std::vector<grid::IndexBox>& sources, double dt, std::int64_t order);
  /// Water [Δx³] a donor carries through a face of its along `axis` (`positive`: the donor
  /// lies on the face's minus side) in a slab of width s cells: its PLIC plane's share.
  double slab_water(std::int64_t donor, int axis, bool positive, double s) const;
  /// The fragments' share of a pass: per part and per whole cell beside them, the change.
  struct FragmentPass {
    std::vector<double> part_delta;
    std::vector<std::pair<std::int64_t, double>> whole_delta;
    double dilation = 0.0;  ///< made in the parts by their dilation terms [Δx³]
  };
  /// The fragments' part of a pass along `axis`, from the pass's starting F: the water each
  /// split face's fragments carry between parts (no part gives more than it holds) and each
  /// part's dilation.
  FragmentPass gather_fragments(int axis, double dt) const;
  /// Applies a pass's fragment changes after the lines' sweep; the wet box and the planes
  /// grow to what changed. Returns the water clipped at F = 0 [Δx³].
  double apply_fragments(const FragmentPass& pass, std::vector<std::int64_t>& cut_now);
  /// The fragments' net flux Σ β u through split face `face` of family `axis`.
  double split_face_flux(int axis, std::int64_t face) const;
  /// The unit normal (towards the air) at cell c: φ's gradient by central differences
  /// (one-sided at the walls), or −∇F where φ is flat there.
  Eigen::Vector3d normal_at(const LevelSet& level_set, const Eigen::Vector3i& c) const;

  grid::UniformGrid m_mac;
  std::vector<double> m_fraction;
  /// The dilation term's weight is 1 in φ^n's liquid cells, 0 elsewhere, but F^n in the
  /// liquid cells a shell cuts: these (cell, F^n), in cell order.
  std::vector<std::pair<std::int64_t, double>> m_cut_weights;
  /// A cut cell's plane n·x = height (unit cube about its centre), n fixed for the step.
  struct Plane {
    std::int64_t cell;
    Eigen::Vector3d normal;
    double height;
  };
  std::vector<Plane> m_planes;           ///< the cells cut so far this step, in the order first cut
  std::vector<std::int32_t>
      m_plane_of;  ///< each cell's entry in m_planes (−1: none; all between steps)
  /// This step's cells with water or φ^n <= 0, bounded: the sweeps change no cell beyond a
  /// cell outside it.
  grid::IndexBox m_wet;
  std::vector<double> m_line_sums;       ///< per line of a pass: clipped, dilated, divergence, out
  double m_clipped_total = 0.0;
  struct CutFace {
    std::int64_t face;
    double fraction, shell_velocity;
  };
  bool m_faces_kept = false;  ///< a projection's faces are kept (before the first, `mac`'s)
  std::array<std::vector<std::pair<std::int64_t, double>>, 3> m_kept;  ///< (face, projected)
  std::array<std::vector<CutFace>, 3> m_cut;    ///< the shells' cut faces since the projection
  std::vector<grid::IndexBox> m_faces_sources;  ///< the emitters whose held faces those are
  /// A face F moves with instead of the MAC's: its place along its line, its velocity.
  struct LineFace {
    int along;
    double u;
  };
  std::array<std::vector<LineFace>, 3> m_line_faces;      ///< per axis, grouped by line
  std::array<std::vector<std::int64_t>, 3> m_line_start;  ///< per axis, each line's first (+ end)
  std::int64_t m_steps = 0;
  std::array<bool, 6> m_open{};
  // Cut cells (set_cut_cells): the parts, their fragments' velocities, the extras' water,
  // per face whether it is split, per cell whether it is cut, each part's fill at the step's
  // start (its dilation weight), each part's room as the passes go.
  const CellParts* m_parts = nullptr;
  const FragmentVelocities* m_fragment_velocity = nullptr;
  const std::vector<Eigen::Vector3d>* m_shell_flux = nullptr;
  std::vector<double> m_part_fraction;
  std::array<std::vector<std::uint8_t>, 3> m_split;
  std::vector<std::uint8_t> m_cut_cell;
  std::vector<double> m_part_fill;
  std::vector<double> m_part_room;  ///< each part's volume as the step's passes sweep it
  std::vector<std::uint8_t> m_part_liquid;
  VolumeFractionStats m_stats;
};

}  // namespace shellflow::grid_fluid
