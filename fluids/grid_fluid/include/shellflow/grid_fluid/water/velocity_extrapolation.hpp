#pragma once
// VelocityExtrapolation: after the projection of a water step only the faces next to a
// liquid cell (and the Neumann faces of shells and walls) hold velocities; §4.4
// (Guendelman et al. 2005) extends them across the surface into a band of a few cells
// so that the next step's advection of velocity and φ has values to interpolate. Per face
// family, the unknown faces with φ below the band (φ at a face: the mean of its two cells;
// a signed distance after reinitialisation) are visited in increasing φ, and each solves the upwind
// discretisation of ∇φ·∇u = 0 from its already known neighbours of lower φ:  u_f = Σ_a (φ_f − φ_a)
// u_a / Σ_a (φ_f − φ_a), one neighbour per axis (the lower of the two), neighbours that are not
// visible (a ray between the face centres meets a shell) ruled out. Linear (the default): within a
// cell of the surface the normal slope of the velocity carries on, ∇φ·∇u = d with d the same
// discretisation's value at the liquid faces, extrapolated constant (Aslam 2004), so that a surface
// between two planes of faces moves with its own velocity. A face with no known visible neighbour
// is invalid and is refilled afterwards (§3: Gauss–Jacobi over valid visible neighbours, the
// object's velocity standing in for the hidden ones). Faces beyond the band are set to 0 and never
// read (the nodes that would read them lie beyond the band too).

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"

namespace shellflow::grid_fluid {

struct ExtrapolationStats {
  std::int64_t known_faces = 0;         ///< faces the projection set (liquid or Neumann)
  std::int64_t extrapolated_faces = 0;  ///< faces filled in φ order
  std::int64_t invalid_faces = 0;       ///< faces refilled (§3)
};

class VelocityExtrapolation {
 public:
  /// `linear`: the first layer of faces above the liquid continues the normal slope.
  VelocityExtrapolation(const grid::UniformGrid& grid, bool linear)
      : m_grid(grid), m_linear(linear) {}

  /// `known[a]` flags (1 byte per face of family a) the faces whose velocity is set: 1 by
  /// the projection, 2 or 3 a Neumann face (a wall's or a shell's velocity, no slope to
  /// continue);
  /// every other face within `width` [m] of the surface is extrapolated, the rest zeroed.
  ExtrapolationStats extrapolate(MacGrid& mac,
                                 const std::array<std::vector<std::uint8_t>, 3>& known,
                                 const LevelSet& level_set, double width,
                                 const ShellGeometry& shells, const geometry::ShellBand* band);

 private:
  grid::UniformGrid m_grid;
  bool m_linear = false;
  std::vector<double> m_face_phi;
  std::vector<std::uint8_t> m_valid;
  /// linear: ∇φ·∇u of the faces within a cell of the surface and the known faces they read,
  /// once computed (a map: a few per cent of the faces).
  std::unordered_map<std::int64_t, double> m_slope;
  std::vector<std::pair<double, std::int64_t>> m_order;
};

}  // namespace shellflow::grid_fluid
