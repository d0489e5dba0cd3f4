#pragma once
// TriangleMesh: a non-owning view of a shell's node positions and triangles
// (sdk::Positions / sdk::Triangles, as in sdk::ShellSurface). Cheap to copy; the viewed
// matrices must outlive it. The fluid keeps one view per shell per time level (n, n+1).

#include <Eigen/Geometry>
#include <array>
#include <vector>

#include "shellflow/geometry/aabb.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::geometry {

/// The three corners of one triangle.
using TriangleCorners = std::array<Eigen::Vector3d, 3>;

class TriangleMesh {
 public:
  TriangleMesh() = default;
  TriangleMesh(const sdk::Positions& positions, const sdk::Triangles& triangles)
      : m_positions(&positions), m_triangles(&triangles) {}
  /// The view of a shell surface at its current positions.
  explicit TriangleMesh(const sdk::ShellSurface& surface)
      : m_positions(&surface.positions), m_triangles(surface.triangles.get()) {}

  int node_count() const { return m_positions ? static_cast<int>(m_positions->rows()) : 0; }
  int triangle_count() const { return m_triangles ? static_cast<int>(m_triangles->rows()) : 0; }
  const sdk::Positions& positions() const { return *m_positions; }
  const sdk::Triangles& triangles() const { return *m_triangles; }

  Eigen::Vector3d node(int i) const { return m_positions->row(i).transpose(); }
  Eigen::Vector3i triangle(int t) const { return m_triangles->row(t).transpose(); }
  TriangleCorners corners(int t) const {
    const auto& tri = *m_triangles;
    return {node(tri(t, 0)), node(tri(t, 1)), node(tri(t, 2))};
  }
  /// Area-weighted normal (x1 - x0) x (x2 - x0): length = twice the area.
  Eigen::Vector3d scaled_normal(int t) const {
    const TriangleCorners c = corners(t);
    return (c[1] - c[0]).cross(c[2] - c[0]);
  }
  double area(int t) const { return 0.5 * scaled_normal(t).norm(); }
  Aabb box(int t) const {
    const TriangleCorners c = corners(t);
    return {c[0].cwiseMin(c[1]).cwiseMin(c[2]), c[0].cwiseMax(c[1]).cwiseMax(c[2])};
  }
  /// Box of every triangle, for a Bvh.
  void boxes(std::vector<Aabb>& out) const;
  /// Box of every triangle over a linear motion from `this` to `end` (same topology).
  void swept_boxes(const TriangleMesh& end, std::vector<Aabb>& out) const;
  /// Bounding box of all nodes.
  Aabb bounds() const;
  /// True when both views share the triangle list size and the node count.
  bool same_topology(const TriangleMesh& other) const {
    return node_count() == other.node_count() && triangle_count() == other.triangle_count();
  }

 private:
  const sdk::Positions* m_positions = nullptr;
  const sdk::Triangles* m_triangles = nullptr;
};

}  // namespace shellflow::geometry
