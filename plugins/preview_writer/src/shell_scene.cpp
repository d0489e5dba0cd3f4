#include "shellflow/preview_writer/shell_scene.hpp"

#include <cmath>

namespace shellflow::preview_writer {

namespace {

/// Möller–Trumbore 1997 ray–triangle test; returns the ray parameter or +inf.
double intersect(const geometry::TriangleCorners& c, const Eigen::Vector3d& origin,
                 const Eigen::Vector3d& direction) {
  const Eigen::Vector3d e1 = c[1] - c[0];
  const Eigen::Vector3d e2 = c[2] - c[0];
  const Eigen::Vector3d p = direction.cross(e2);
  const double det = e1.dot(p);
  const double miss = std::numeric_limits<double>::infinity();
  // Relative to the edge lengths: a ray in the plane of the triangle (or a degenerate
  // triangle) has det = 0 up to round-off and sees no surface.
  if (std::abs(det) <= 1e-14 * e1.norm() * e2.norm()) return miss;
  const double inv = 1.0 / det;
  const Eigen::Vector3d t = origin - c[0];
  const double u = t.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return miss;
  const Eigen::Vector3d q = t.cross(e1);
  const double v = direction.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return miss;
  return e2.dot(q) * inv;
}

}  // namespace

ShellScene::ShellScene(sdk::ShellSet shells) {
  for (const auto& shell : shells) {
    if (shell.triangle_count() == 0) continue;
    const geometry::TriangleMesh mesh(shell);
    m_hierarchies.emplace_back(mesh);
    m_bounds.extend(mesh.bounds());
  }
}

void ShellScene::triangle_boxes(std::vector<geometry::Aabb>& out) const {
  std::vector<geometry::Aabb> boxes;
  for (const auto& hierarchy : m_hierarchies) {
    hierarchy.mesh().boxes(boxes);
    out.insert(out.end(), boxes.begin(), boxes.end());
  }
}

ShellHit ShellScene::first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                               double max_distance) const {
  ShellHit best;
  best.distance = max_distance;
  int best_shell = -1;
  int best_triangle = -1;
  const Eigen::Vector3d end = origin + max_distance * direction;
  for (size_t h = 0; h < m_hierarchies.size(); ++h) {
    const auto& hierarchy = m_hierarchies[h];
    hierarchy.triangles_near_segment(origin, end, 0.0, [&](int triangle) {
      const double s = intersect(hierarchy.mesh().corners(triangle), origin, direction);
      if (s > 0.0 && s <= best.distance) {
        best.distance = s;
        best_shell = static_cast<int>(h);
        best_triangle = triangle;
      }
      return false;  // keep looking: the traversal is not ordered by distance
    });
  }
  if (best_shell < 0) return {};
  best.normal = m_hierarchies[best_shell].mesh().scaled_normal(best_triangle).normalized();
  return best;
}

}  // namespace shellflow::preview_writer
