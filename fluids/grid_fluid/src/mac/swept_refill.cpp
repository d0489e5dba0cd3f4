#include "shellflow/grid_fluid/mac/swept_refill.hpp"

#include "shellflow/geometry/swept_point_invalidator.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

SweptRefill::SweptRefill(const grid::UniformGrid& grid, double ambient_temperature)
    : m_grid(grid), m_ambient(ambient_temperature) {}

SweptRefillStats SweptRefill::run(const ShellGeometry& start, const ShellGeometry& end,
                                  NodeFields& fields) {
  SweptRefillStats stats;
  const std::int64_t nodes = m_grid.size(Location::Node);
  if (m_node_invalid.size() != static_cast<size_t>(nodes)) {
    m_node_invalid.assign(nodes, 0);
    m_node_valid.assign(nodes, 1);
    m_node_valid_before.assign(nodes, 1);
    for (int a = 0; a < 3; ++a) m_face_swept[a].assign(m_grid.size(face_location(a)), 0);
    if (m_track_cells) m_cell_swept.assign(m_grid.size(Location::Cell), 0);
  }
  // Reset last step's flags (only where they were set).
  for (const std::int64_t i : m_invalid_list) {
    m_node_invalid[i] = 0;
    m_node_valid_before[i] = 1;
  }
  m_invalid_list.clear();
  for (int a = 0; a < 3; ++a) {
    for (const std::int64_t f : m_face_lists[a]) m_face_swept[a][f] = 0;
    m_face_lists[a].clear();
  }
  for (const std::int64_t c : m_cell_list) m_cell_swept[c] = 0;
  m_cell_list.clear();
  if (start.empty() || end.empty() || start.shell_count() != end.shell_count()) return stats;

  const geometry::SweptPointInvalidator invalidator(m_grid, end.epsilon());
  for (int s = 0; s < start.shell_count(); ++s) {
    if (!start.mesh(s).same_topology(end.mesh(s))) continue;
    invalidator.invalidate(Location::Node, start.mesh(s), end.mesh(s), m_node_invalid,
                           m_invalid_list);
    for (int a = 0; a < 3; ++a)
      invalidator.invalidate(face_location(a), start.mesh(s), end.mesh(s), m_face_swept[a],
                             m_face_lists[a]);
    if (m_track_cells)
      invalidator.invalidate(Location::Cell, start.mesh(s), end.mesh(s), m_cell_swept, m_cell_list);
  }
  stats.invalid_nodes = static_cast<std::int64_t>(m_invalid_list.size());
  for (int a = 0; a < 3; ++a) stats.invalid_faces += static_cast<std::int64_t>(m_face_lists[a].size());
  if (m_invalid_list.empty()) return stats;

  // The refill reads invalid nodes and (layer by layer) their one-ring: copy the nodes
  // within the refill's reach into the AoS scratch.
  m_scratch.resize(nodes);
  m_scratch.clear();
  const geometry::GaussJacobiRefill refill(m_grid, Location::Node);
  const Eigen::Vector3i n = m_grid.counts(Location::Node);
  const std::int64_t stride[3] = {1, n.x(), std::int64_t{n.x()} * n.y()};
  const auto copy = [&](std::int64_t node) {
    if (!m_scratch.contains(node)) m_scratch.insert(node, fields.sample(node));
  };
  for (const std::int64_t i : m_invalid_list) {
    m_node_valid[i] = 0;
    m_node_valid_before[i] = 0;
    copy(i);
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, i);
    for (int axis = 0; axis < 3; ++axis)
      for (const int side : {-1, 1}) {
        const int c = ijk[axis] + side;
        if (c >= 0 && c < n[axis]) copy(i + side * stride[axis]);
      }
  }
  const auto& caster = end.caster();
  const auto visible = refill.wedge_visibility(caster);
  const auto object_value = [&](std::int64_t from, std::int64_t to) {
    const Eigen::Vector3d a = m_grid.position(Location::Node, from);
    const Eigen::Vector3d b = m_grid.position(Location::Node, to);
    NodeSample v;
    v.head<3>() = end.object_velocity(a, b);
    v[3] = 0.0;
    v[4] = m_ambient;
    return v;
  };
  stats.refill = refill.run(m_scratch, m_node_valid, m_invalid_list, visible, object_value);
  for (const std::int64_t i : m_invalid_list) fields.set(i, m_scratch[i]);
  return stats;
}

}  // namespace shellflow::grid_fluid
