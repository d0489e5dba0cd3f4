#pragma once
// NodeFields: the values the node-based scheme of §4.2 carries on grid nodes — velocity
// (three flat arrays, structure of arrays), smoke density and temperature — all indexed
// by UniformGrid::index(Location::Node, ...), plus trilinear sampling.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::grid_fluid {

/// One node's values, as a small vector for averaging (refill, interpolation):
/// (u, v, w, density, temperature).
using NodeSample = Eigen::Matrix<double, 5, 1>;

class NodeFields {
 public:
  NodeFields() = default;
  /// Zero velocity and density, temperature `ambient_temperature` [K]. Without `smoke`
  /// (water) only the velocity is stored; samples carry zero density and temperature.
  /// Without `temperature` (smoke whose sources set none) no temperature is stored and
  /// samples carry the ambient one.
  NodeFields(const grid::UniformGrid& grid, double ambient_temperature, bool smoke = true,
             bool temperature = true);

  bool has_smoke() const { return !m_density.empty(); }
  bool has_temperature() const { return !m_temperature.empty(); }
  /// The stored fields, in NodeSample order: velocity, then density and temperature.
  int field_count() const { return 3 + (has_smoke() ? 1 : 0) + (has_temperature() ? 1 : 0); }

  std::int64_t size() const { return static_cast<std::int64_t>(m_velocity[0].size()); }
  std::vector<double>& velocity(int axis) { return m_velocity[axis]; }
  const std::vector<double>& velocity(int axis) const { return m_velocity[axis]; }
  const std::array<std::vector<double>, 3>& velocities() const { return m_velocity; }
  std::vector<double>& density() { return m_density; }
  const std::vector<double>& density() const { return m_density; }
  std::vector<double>& temperature() { return m_temperature; }
  const std::vector<double>& temperature() const { return m_temperature; }

  NodeSample sample(std::int64_t node) const {
    NodeSample s;
    if (has_smoke()) {
      s << m_velocity[0][node], m_velocity[1][node], m_velocity[2][node], m_density[node],
          has_temperature() ? m_temperature[node] : m_ambient;
    } else {
      s << m_velocity[0][node], m_velocity[1][node], m_velocity[2][node], 0.0, 0.0;
    }
    return s;
  }
  void set(std::int64_t node, const NodeSample& s) {
    for (int a = 0; a < 3; ++a) m_velocity[a][node] = s[a];
    if (!has_smoke()) return;
    m_density[node] = s[3];
    if (has_temperature()) m_temperature[node] = s[4];
  }
  Eigen::Vector3d velocity_at(std::int64_t node) const {
    return {m_velocity[0][node], m_velocity[1][node], m_velocity[2][node]};
  }

 private:
  std::array<std::vector<double>, 3> m_velocity;
  std::vector<double> m_density;
  std::vector<double> m_temperature;
  double m_ambient = 0.0;  ///< the temperature of samples when none is stored
};

/// Corner c's offset from its cell's corner 0 (bit 0: +x, bit 1: +y, bit 2: +z).
inline Eigen::Vector3i corner_step(int c) {
  return Eigen::Vector3i(c & 1, (c >> 1) & 1, c >> 2);
}

/// The cell of the node lattice holding a point (clamped into the grid), and the
/// trilinear weights' fractions inside it.
struct NodeStencil {
  Eigen::Vector3i base;      ///< lower corner node
  Eigen::Vector3d fraction;  ///< in [0, 1]^3
  /// Flat index of corner c (bit 0: +x, bit 1: +y, bit 2: +z).
  std::int64_t corner(const grid::UniformGrid& grid, int c) const {
    return grid.index(grid::Location::Node, base + corner_step(c));
  }
  double weight(int c) const {
    return ((c & 1) ? fraction.x() : 1.0 - fraction.x()) *
           (((c >> 1) & 1) ? fraction.y() : 1.0 - fraction.y()) *
           (((c >> 2) & 1) ? fraction.z() : 1.0 - fraction.z());
  }
};
/// The stencil of point q given in cells from the grid's origin, q = (p − origin)/Δx: a
/// point on the grid's upper face lies in the last cell at fraction 1.
inline NodeStencil node_stencil_in_cells(const Eigen::Vector3i& cells, const Eigen::Vector3d& q) {
  NodeStencil s;
  for (int a = 0; a < 3; ++a) {
    const double x = std::clamp(q[a], 0.0, static_cast<double>(cells[a]));
    const int i = std::min(static_cast<int>(x), cells[a] - 1);  // x >= 0: truncation floors
    s.base[a] = i;
    s.fraction[a] = x - i;
  }
  return s;
}
/// The stencil of world point p.
inline NodeStencil node_stencil(const grid::UniformGrid& grid, const Eigen::Vector3d& p) {
  return node_stencil_in_cells(grid.cells(), (p - grid.origin()) / grid.dx());
}
/// Flat offsets of a cell's 8 corner nodes from its corner 0, in NodeStencil's corner
/// order: a row loop's corners without index arithmetic per corner.
inline std::array<std::int64_t, 8> node_corner_offsets(const grid::UniformGrid& grid) {
  const Eigen::Vector3i n = grid.counts(grid::Location::Node);
  const std::int64_t sy = n.x(), sz = std::int64_t(n.x()) * n.y();
  return {0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1};
}

}  // namespace shellflow::grid_fluid
