#pragma once
// SmokeVolume: a density field seen by a ray marcher. Trilinear interpolation between
// samples, the value of the nearest border sample beyond the outer samples (so a
// cell-centred field fills its whole cells), zero outside the field's box (TrilinearField).
//
// optical_depth() integrates ρ along a ray segment by the midpoint rule with step h
// (the last step clipped to the segment's end). The trilinear interpolant is linear
// between sample planes, so the rule is exact except in steps containing a sample plane
// crossing, each of which errs by at most |slope jump| h² / 8 (slope jump across a
// plane: at most 2 max|ρ| / dx).

#include <Eigen/Core>

#include "shellflow/preview_writer/trilinear_field.hpp"
#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

class SmokeVolume {
 public:
  /// A view of `field` (one component); the field's data must outlive the volume.
  /// @throw std::invalid_argument when the field is not a non-empty scalar with dx > 0.
  explicit SmokeVolume(const sdk::FieldView& field);

  /// Interpolated density at world point x (0 outside the box).
  double density(const Eigen::Vector3d& x) const;
  /// ∫ ρ ds over origin + s·direction, s in [s0, s1] clipped to the box; step h [m];
  /// stops early once the integral exceeds `max_depth`.
  double optical_depth(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double s0,
                       double s1, double h, double max_depth) const;
  /// Ray parameters [s_in, s_out] where the ray is inside the box; false when it misses.
  bool clip(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double& s_in,
            double& s_out) const;

  double dx() const { return m_field.dx(); }
  const Eigen::Vector3d& lower() const { return m_field.lower(); }
  const Eigen::Vector3d& upper() const { return m_field.upper(); }

 private:
  TrilinearField m_field;
};

}  // namespace shellflow::preview_writer
