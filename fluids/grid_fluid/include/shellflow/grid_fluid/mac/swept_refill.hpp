#pragma once
// SweptRefill: after the shells move from x^n to x^{n+1} (§3, §4.1), every node a
// triangle passed through (or that starts or ends inside a wedge) holds a value from the
// other side: it is invalidated (geometry::SweptPointInvalidator) and refilled by
// Gauss–Jacobi averaging of valid visible neighbours, object values standing in where no
// neighbour is visible (geometry::GaussJacobiRefill): the object velocity at n+1, zero
// density, the ambient temperature. Faces swept by the shells are flagged too, for the
// §4.2 transfer back to the faces.

#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/geometry/gauss_jacobi_refill.hpp"
#include "shellflow/grid/sparse_samples.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {

struct SweptRefillStats {
  std::int64_t invalid_nodes = 0;
  std::int64_t invalid_faces = 0;
  geometry::RefillStats refill;
};

class SweptRefill {
 public:
  SweptRefill(const grid::UniformGrid& grid, double ambient_temperature);
  /// run() also lists the cell centres the shells sweep (water whose φ lives on them).
  void track_cells() { m_track_cells = true; }

  /// Invalidates and refills `fields` for the motion start → end (same shells, same
  /// order, same topology). Afterwards node_valid_before()[i] is 0 for the nodes that were
  /// invalid and face_swept()[a] flags the swept faces (cleared on the next run()).
  SweptRefillStats run(const ShellGeometry& start, const ShellGeometry& end, NodeFields& fields);

  std::span<const std::uint8_t> node_valid_before() const { return m_node_valid_before; }
  /// The cell centres swept (track_cells(); empty otherwise).
  std::span<const std::int64_t> swept_cells() const { return m_cell_list; }
  const std::array<std::vector<std::uint8_t>, 3>& face_swept() const { return m_face_swept; }

 private:
  grid::UniformGrid m_grid;
  double m_ambient;
  std::vector<std::uint8_t> m_node_invalid;       ///< scratch for the invalidator
  std::vector<std::uint8_t> m_node_valid;         ///< the refill's valid flags
  std::vector<std::uint8_t> m_node_valid_before;  ///< 0 where swept this step
  std::vector<std::int64_t> m_invalid_list;
  std::array<std::vector<std::uint8_t>, 3> m_face_swept;
  std::array<std::vector<std::int64_t>, 3> m_face_lists;
  bool m_track_cells = false;
  std::vector<std::uint8_t> m_cell_swept;
  std::vector<std::int64_t> m_cell_list;
  /// Copies of the nodes the refill may read: the invalid ones and their one-ring.
  grid::SparseSamples<NodeSample> m_scratch;
};

}  // namespace shellflow::grid_fluid
