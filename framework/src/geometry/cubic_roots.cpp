#include "shellflow/geometry/cubic_roots.hpp"

#include <algorithm>
#include <cmath>

namespace shellflow::geometry {

namespace {

/// Real roots of a t^2 + b t + c in the open interval (0, 1), numerically stable form
/// (Press et al., Numerical Recipes §5.6). Returns the count written to `out`.
int quadratic_roots_in_unit(double a, double b, double c, double out[2]) {
  int n = 0;
  const auto keep = [&](double t) {
    if (t > 0.0 && t < 1.0 && std::isfinite(t)) out[n++] = t;
  };
  if (a == 0.0) {
    if (b != 0.0) keep(-c / b);
    return n;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return 0;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  keep(q / a);
  if (q != 0.0) keep(c / q);
  if (n == 2 && out[0] > out[1]) std::swap(out[0], out[1]);
  return n;
}

/// Bisection stops when the bracket is this narrow: far below any time resolution a
/// step needs, and ~10 ulps of 1.
constexpr double kTimeResolution = 1e-15;

}  // namespace

NearRoots cubic_near_roots(const std::array<double, 4>& c, double tolerance) {
  NearRoots result;
  double breaks[4];
  int nb = 0;
  breaks[nb++] = 0.0;
  double critical[2];
  const int nc = quadratic_roots_in_unit(3.0 * c[3], 2.0 * c[2], c[1], critical);
  for (int i = 0; i < nc; ++i) breaks[nb++] = critical[i];
  breaks[nb++] = 1.0;

  const auto add = [&result](double t) {
    if (result.count > 0 && std::abs(result.times[result.count - 1] - t) <= kTimeResolution) {
      return;
    }
    result.times[result.count++] = t;
  };

  bool all_near = true;
  for (int piece = 0; piece + 1 < nb; ++piece) {
    double ta = breaks[piece];
    double tb = breaks[piece + 1];
    const double fa = evaluate_cubic(c, ta);
    const double fb = evaluate_cubic(c, tb);
    all_near = all_near && std::abs(fa) <= tolerance && std::abs(fb) <= tolerance;
    if (std::abs(fa) <= tolerance) add(ta);
    if (fa != 0.0 && fb != 0.0 && ((fa < 0.0) != (fb < 0.0))) {
      // Exactly one root in a monotone piece with a sign change: bisect.
      const bool rising = fa < 0.0;
      for (int it = 0; it < 200 && tb - ta > kTimeResolution; ++it) {
        const double tm = 0.5 * (ta + tb);
        if (tm <= ta || tm >= tb) break;
        const double fm = evaluate_cubic(c, tm);
        if (fm == 0.0) {
          ta = tb = tm;
          break;
        }
        if ((fm < 0.0) == rising) {
          ta = tm;
        } else {
          tb = tm;
        }
      }
      add(0.5 * (ta + tb));
    }
    // Without a sign change the piece is monotone, so |p| is smallest at an end.
    if (std::abs(fb) <= tolerance) add(breaks[piece + 1]);
  }
  result.everywhere_near_zero = all_near;
  std::sort(result.times.begin(), result.times.begin() + result.count);
  return result;
}

}  // namespace shellflow::geometry
