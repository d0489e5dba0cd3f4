#pragma once
// LevelSetAdvector: semi-Lagrangian advection of the water's level set on the nodes
// (§4.4.1, Guendelman et al. 2005; trilinear, first order in space, as Enright, Losasso,
// Fedkiw 2005 showed suffices under the particle level set). Each node traces the same ray
// as its velocity (§4.1: clipped against wedges of doubled thickness 2ε, so the base point
// is visible from the node); of the 8 nodes of the base point's cell, one that is not
// visible from the base point takes the wetter (the lower φ) of two continuations of the
// base point's side across the shell: linear, 2φ(d) − φ(2d − c) through each visible
// corner d of its nearest ring (one edge, then a face diagonal, then the cell's diagonal
// away) whose mirror node 2d − c is visible too, averaged; and constant, the mean of that
// nearest ring of visible corners. The linear one keeps a film on a shell thinner than a
// cell: its dry nodes hold less than their distance to the shell, and constant continuation
// reads them as the water's φ, a bias upwards that erased such a film. The constant one
// keeps water held against a moving wall, whose small |φ| there the linear one reads as
// the water ending at the wall. A ray the shell would clip slides along the shell instead, its
// normal part relative to the shell taken out (the water next to a shell neither passes
// through it nor leaves it; the node velocities there, averaged from faces the shell
// closes per axis, carry such a part that is not the water's). Where the slid ray meets a
// shell too, the clipped ray takes the constant continuation alone: it starts at the
// shell, where a field flowing off it continued linearly would steepen its own slope
// every step and make water behind the shell. With no visible
// node in the cell the node is invalid and refilled afterwards (refill(): §3,
// Gauss–Jacobi over valid visible neighbours, then the positive distance to the object).
// Nodes outside the shell band take the plain trilinear path.
// Each node's ray follows the velocity at its midpoint (Trace::Midpoint, second order in
// time: the velocity at x − u dt/2, from the corners seen from there next to a shell) rather
// than the node's own (Trace::Euler, the paper's): in irrotational flow det(∇u) < 0, and
// the Euler map x → x − u dt grows the traced water by O(dt |∇u|²) a second.
// With `maccormack` (Selle, Fedkiw, Kim, Liu, Rossignac 2008; experimental) each step
// traces the rays forward and back and corrects the forward value by half the round trip's
// error, clamped to the values the forward stencil interpolated (after the ring rule):
// second order where φ is smooth, never a new extremum. Trilinear alone shrinks curved
// water by O(Δx^2 κ) a step; the particles of §4.4.2 are the paper's cure. Not the
// default: it made a dam break unstable.

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/water/boundary_phi.hpp"

namespace shellflow::grid_fluid {

class LevelSetAdvector {
 public:
  /// Which velocity a node's ray follows (see above).
  enum class Trace { Midpoint, Euler };

  explicit LevelSetAdvector(const grid::UniformGrid& grid, bool maccormack = false,
                            Trace trace = Trace::Midpoint)
      : m_grid(grid),
        m_maccormack(maccormack),
        m_trace(trace),
        m_corner_offset(node_corner_offsets(grid)) {}

  bool maccormack() const { return m_maccormack; }

  /// out = φ advected over dt by the node velocities of `velocity`. Appends to `invalid`
  /// the nodes whose stencil saw no visible node (their `out` value is left as `in`'s).
  /// `ghost`, when given, reads φ at departure points beyond the lattice's box outside the
  /// shell band (the cell-centred φ's open and inflow sides); else φ is continued constant.
  /// Nodes with |φ| > `reach` [m] keep their φ, but in the shell band and, with a ghost,
  /// within `reach` of the lattice's sides: a narrow band. With φ a distance and `reach` at
  /// least max |u| |dt| + √3Δx (the ray and its stencil), the step cannot change their sign,
  /// and reinitialisation sets their magnitude anew.
  void advect(std::span<const double> in, const NodeFields& velocity, double dt,
              const ShellGeometry& shells, const geometry::ShellBand* band, std::span<double> out,
              std::vector<std::int64_t>& invalid, const BoundaryPhi* ghost = nullptr,
              double reach = std::numeric_limits<double>::infinity());

  /// φ at `base` by trilinear interpolation over its cell, each node not visible from
  /// `base` replaced by the rule above (without `linear`, the constant continuation alone);
  /// nullopt when no node of the cell is visible. `range`, when given,
  /// receives the least and greatest of the 8 values interpolated.
  std::optional<double> sample_visible(std::span<const double> phi, const Eigen::Vector3d& base,
                                       const ShellGeometry& shells, double* range = nullptr,
                                       bool linear = true) const;

  /// The φ the 8 corners of `st`'s cell hold as seen from p (in `st`'s corner order): a
  /// corner p sees keeps its own; one across a shell takes p's side continued (the rule
  /// above; without `linear`, the constant continuation alone). Returns the corners p sees
  /// (bit c for corner c; 0: none, and `value` is then the corners' own φ).
  unsigned seen_corner_values(std::span<const double> phi, const Eigen::Vector3d& p,
                              const NodeStencil& st, const ShellGeometry& shells, double value[8],
                              bool linear = true) const;

  /// §3 refill of the listed invalid nodes (`valid` is 0 there, 1 elsewhere; all 1 on
  /// return): Gauss–Jacobi over valid visible neighbours, the positive distance to the
  /// object along the ray standing in for neighbours that are not visible.
  void refill(std::span<double> phi, std::span<std::uint8_t> valid,
              std::span<const std::int64_t> invalid, const ShellGeometry& shells) const;

 private:
  /// One semi-Lagrangian pass over dt (negative: forwards along the velocity); `range`,
  /// when given, receives each node's stencil bounds (2 per node), and `clamped` the nodes
  /// whose ray left the lattice and was clamped to it (no round trip there to correct by).
  void trace(std::span<const double> in, const NodeFields& velocity, double dt,
             const ShellGeometry& shells, const geometry::ShellBand* band, std::span<double> out,
             double* range, std::vector<std::int64_t>& invalid, const BoundaryPhi* ghost,
             double reach, std::vector<std::int64_t>* clamped = nullptr) const;
  /// The shell point an air node x (φ = p > 0) is within Δx of, unless it lies on an open
  /// edge (past which water runs on): the shell off_shells measures u against.
  std::optional<ShellContact> air_contact(const Eigen::Vector3d& x, double p,
                                          const ShellGeometry& shells) const;
  /// The velocity node x traces with: u, except at an air node in `contact` with a shell
  /// (air_contact) where its normal part relative to the shell is taken out:
  ///  - where u moves x off the shell: extrapolated from the water, that part carried the
  ///    shell's wet side out into the air (water from nothing);
  ///  - where u moves x onto the shell over a film between x and the shell (film_beneath):
  ///    the film's surface moves only as fast as it thins, and that part dried the film.
  ///    Water that comes at the shell from beyond x (φ falling off it) keeps it.
  Eigen::Vector3d off_shells(const Eigen::Vector3d& x, const Eigen::Vector3d& u, double p,
                             const ShellContact& contact, std::span<const double> phi, double dt,
                             const ShellGeometry& shells) const;
  /// The velocity the ray from node x follows over dt (Trace::Midpoint): the node
  /// velocities interpolated at x − u dt/2, u being the node's own (after off_shells). In
  /// the shell band (`in_band` not empty) only the corners seen from there count (a corner
  /// outside the band is at least the band's margin, 2Δx, from any shell, farther than the
  /// corner's distance from the midpoint: seen), and off_shells applies again for an air
  /// node in `contact` with a shell. u itself where that point lies across a shell or sees
  /// no corner.
  Eigen::Vector3d midpoint_velocity(const Eigen::Vector3d& x, const Eigen::Vector3d& u,
                                    const NodeFields& velocity, std::span<const double> phi,
                                    std::int64_t node, double dt,
                                    std::span<const std::uint8_t> in_band,
                                    const ShellContact* contact, const ShellGeometry& shells,
                                    double epsilon) const;
  /// Whether φ (p at x, > 0) says water lies between x and the shell it is in `contact`
  /// with: φ a cell further off, on x's side, is larger, and the line through the two
  /// falls below zero before the shell.
  bool film_beneath(const Eigen::Vector3d& x, double p, const ShellContact& contact,
                    std::span<const double> phi, const ShellGeometry& shells) const;
  /// Where the path back from x to `departure` goes once the shell it meets stops it
  /// from crossing: along the shell, with the shell's own motion normal to it (the water
  /// next to a shell does not pass through it, nor leave it). None where the path meets
  /// no shell or the slid path meets one.
  std::optional<Eigen::Vector3d> slide_along_shell(const Eigen::Vector3d& x,
                                                   const Eigen::Vector3d& departure, double dt,
                                                   const ShellGeometry& shells,
                                                   double epsilon) const;

  grid::UniformGrid m_grid;
  bool m_maccormack = false;
  Trace m_trace = Trace::Midpoint;
  std::array<std::int64_t, 8> m_corner_offset;  ///< node_corner_offsets(m_grid)
  std::vector<double> m_range;  ///< per node: the forward stencil's least, greatest value
  std::vector<double> m_back;   ///< the forward result traced back
  std::vector<std::int64_t> m_back_invalid;  ///< nodes the backward trace could not sample
  std::vector<std::int64_t> m_clamped;       ///< nodes either trace clamped to the lattice
};

}  // namespace shellflow::grid_fluid
