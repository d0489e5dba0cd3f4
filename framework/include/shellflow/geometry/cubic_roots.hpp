#pragma once
// Robust root isolation for a cubic on [0, 1], the time parameter of one step (§3: the
// coplanarity times of a point and a linearly moving triangle, as in Bridson, Fedkiw,
// Anderson 2002). The interval is split at the roots of the derivative into monotone
// pieces; a piece whose ends differ in sign holds exactly one root, refined by bisection
// (it never leaves its bracket, so no root is lost to a bad Newton step); a piece without
// a sign change reports its end nearest to zero when that end is within `tolerance` of
// zero (a tangential touch, or a root lost to round-off).

#include <array>

namespace shellflow::geometry {

struct NearRoots {
  std::array<double, 12> times{};  ///< ascending, in [0, 1]
  int count = 0;
  /// |p(t)| <= tolerance on all of [0, 1] (the polynomial is zero up to the tolerance).
  bool everywhere_near_zero = false;
};

/// Roots and near-roots in [0, 1] of c[0] + c[1] t + c[2] t^2 + c[3] t^3.
NearRoots cubic_near_roots(const std::array<double, 4>& c, double tolerance);

/// Evaluates c[0] + c[1] t + c[2] t^2 + c[3] t^3 (Horner).
inline double evaluate_cubic(const std::array<double, 4>& c, double t) {
  return ((c[3] * t + c[2]) * t + c[1]) * t + c[0];
}

}  // namespace shellflow::geometry
