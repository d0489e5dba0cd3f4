#pragma once
// WedgeCaster: visibility between two points across thin shells (§3, Fig. 3, after
// Bridson, Fedkiw, Anderson 2002). Each triangle is thickened into a wedge: the face
// pushed ±ε/2 along its normal, and, so that neighbouring wedges overlap with no gap
// along a shared edge or at a shared vertex, the edges and vertices rounded by ε/2 too.
// The wedge of triangle T is exactly {x : dist(x, T) <= ε/2} (T's ε/2-neighbourhood:
// the prism over the face plus capsules around the edges and balls at the vertices).
//
// No false "visible": the union of the wedges is the ε/2-neighbourhood of the whole
// surface, so a segment that crosses the surface anywhere (a face, an edge, a vertex)
// comes within distance 0 of some triangle and is reported blocked whenever the
// computed distance errs by less than ε/2 — round-off is ~1e-16 of the coordinates,
// so any ε above ~1e-12 of the domain size is safe.
//
// Classification of B seen from A (Fig. 3 right):
//   Inside   B lies in some wedge;
//   Occluded B is in no wedge but the segment [A, B] touches a wedge;
//   Visible  the segment touches no wedge.
// A reference point that itself lies inside a wedge therefore sees nothing as Visible
// (such points are invalid anyway, §3).

#include <optional>
#include <vector>

#include "shellflow/geometry/triangle_bvh.hpp"

namespace shellflow::geometry {

enum class Visibility { Visible, Inside, Occluded };

/// Where a segment first meets a wedge: the triangle, the segment parameter of the
/// closest approach to it, and the barycentric coordinates of the triangle's closest
/// point (to interpolate object values such as the shell velocity there, §3, §4.1).
struct WedgeHit {
  int shell = -1;
  int triangle = -1;
  double s = 1.0;
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
};

class WedgeCaster {
 public:
  /// §4.1: semi-Lagrangian rays use wedges twice as thick, ε' = 2ε.
  static constexpr double kSemiLagrangianFactor = 2.0;

  /// `epsilon` > 0: the full wedge thickness ε (2011 PhysBAM: 1e-3 × the smallest dx).
  /// The shells are held by pointer and must outlive the caster (and be updated in place).
  WedgeCaster(std::vector<const TriangleBvh*> shells, double epsilon);
  WedgeCaster(const TriangleBvh& shell, double epsilon)
      : WedgeCaster(std::vector<const TriangleBvh*>{&shell}, epsilon) {}

  double epsilon() const { return m_epsilon; }
  /// ε' = 2ε of §4.1.
  double semi_lagrangian_epsilon() const { return kSemiLagrangianFactor * m_epsilon; }
  std::span<const TriangleBvh* const> shells() const { return m_shells; }

  /// Is p inside some wedge of thickness `epsilon` (distance to the surface <= ε/2)?
  bool inside(const Eigen::Vector3d& p, double epsilon) const;
  bool inside(const Eigen::Vector3d& p) const { return inside(p, m_epsilon); }

  /// Does segment [a, b] touch some wedge of thickness `epsilon`?
  bool blocked(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double epsilon) const;
  bool blocked(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return blocked(a, b, m_epsilon);
  }

  /// B seen from A with wedges of thickness `epsilon`.
  Visibility classify(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double epsilon) const;
  Visibility classify(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return classify(a, b, m_epsilon);
  }

  /// The wedge the segment meets first (smallest parameter of closest approach), or none.
  std::optional<WedgeHit> first_hit(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    double epsilon) const;
  std::optional<WedgeHit> first_hit(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return first_hit(a, b, m_epsilon);
  }

 private:
  std::vector<const TriangleBvh*> m_shells;
  double m_epsilon;
};

}  // namespace shellflow::geometry
