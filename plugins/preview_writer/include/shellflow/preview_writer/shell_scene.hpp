#pragma once
// ShellScene: the first shell triangle along a ray, for the preview renderer's depth
// test. One box hierarchy per shell (geometry::TriangleBvh), built per frame; a ray is
// tested against the triangles whose boxes its segment touches (Möller–Trumbore 1997).

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "shellflow/geometry/triangle_bvh.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::preview_writer {

struct ShellHit {
  double distance = std::numeric_limits<double>::infinity();  ///< ray parameter; inf: none
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();           ///< unit, either side
  bool hit() const { return distance < std::numeric_limits<double>::infinity(); }
};

class ShellScene {
 public:
  /// Views `shells` (their positions must outlive the scene).
  explicit ShellScene(sdk::ShellSet shells);

  /// The nearest triangle crossing origin + s·direction for s in (0, max_distance].
  ShellHit first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                     double max_distance) const;

  bool empty() const { return m_hierarchies.empty(); }
  /// Appends the box of every triangle of every shell to `out`.
  void triangle_boxes(std::vector<geometry::Aabb>& out) const;
  /// Box of all shells (empty box when none).
  const geometry::Aabb& bounds() const { return m_bounds; }

 private:
  std::vector<geometry::TriangleBvh> m_hierarchies;
  geometry::Aabb m_bounds;
};

}  // namespace shellflow::preview_writer
