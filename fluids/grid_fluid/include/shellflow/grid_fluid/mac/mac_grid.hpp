#pragma once
// MacGrid: the persistent state of the staggered (MAC) grid of §4.2–4.3 — one normal
// velocity component per face (three flat arrays, FaceX/FaceY/FaceZ of
// grid::UniformGrid) and one pressure per cell. Every array is indexed by
// UniformGrid::index of its location (x fastest). Double precision throughout.

#include <array>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::grid_fluid {

/// The face family holding velocity component `axis` (0: FaceX, 1: FaceY, 2: FaceZ).
inline grid::Location face_location(int axis) {
  return static_cast<grid::Location>(static_cast<int>(grid::Location::FaceX) + axis);
}

class MacGrid {
 public:
  MacGrid() = default;
  explicit MacGrid(const grid::UniformGrid& grid);

  const grid::UniformGrid& grid() const { return m_grid; }
  double dx() const { return m_grid.dx(); }

  /// Normal velocity on the faces of family `axis` [m/s].
  std::vector<double>& face_velocity(int axis) { return m_face_velocity[axis]; }
  const std::vector<double>& face_velocity(int axis) const { return m_face_velocity[axis]; }
  /// Cell-centred pressure [Pa / (kg/m^3)] (the fluid density is absorbed, §4 eq. (1)).
  std::vector<double>& pressure() { return m_pressure; }
  const std::vector<double>& pressure() const { return m_pressure; }

  /// Largest |u| over all faces.
  double max_face_speed() const;
  /// Σ over the six faces of cell `cell` of the outward normal velocity (the discrete
  /// divergence times dx) [m/s].
  double outward_flux(const Eigen::Vector3i& cell) const;

 private:
  grid::UniformGrid m_grid;
  std::array<std::vector<double>, 3> m_face_velocity;
  std::vector<double> m_pressure;
};

}  // namespace shellflow::grid_fluid
