#pragma once
// A piecewise-linear translation path for attached nodes, holding the first and last
// keys outside the key range (as PhysBAM's INTERPOLATION_CURVE).

#include <Eigen/Core>
#include <vector>

namespace shellflow::cloth {

class KinematicPath {
 public:
  KinematicPath() = default;
  /// `times` increasing [s]; `translations[k]` the offset [m] from the rest position at times[k].
  KinematicPath(std::vector<double> times, std::vector<Eigen::Vector3d> translations);
  Eigen::Vector3d translation(double t) const;

 private:
  std::vector<double> m_times;
  std::vector<Eigen::Vector3d> m_translations;
};

}  // namespace shellflow::cloth
