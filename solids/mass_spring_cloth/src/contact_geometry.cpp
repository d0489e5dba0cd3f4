#include "mass_spring_cloth/contact_geometry.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace shellflow::cloth {

Eigen::Vector3d closest_point_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {1.0 - v, v, 0.0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {1.0 - w, 0.0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - w, w};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {1.0 - v - w, v, w};
}

Eigen::Vector2d closest_points_segments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1) {
  // Ericson 2005, §5.1.9.
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double tiny = 1e-30;
  double s = 0.0, t = 0.0;
  if (a <= tiny && e <= tiny) return {0.0, 0.0};
  if (a <= tiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= tiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > tiny * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {s, t};
}

namespace {

double triple(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return a.cross(b).dot(c);
}

}  // namespace

int coplanarity_times(const std::array<Eigen::Vector3d, 4>& x,
                      const std::array<Eigen::Vector3d, 4>& d, std::array<double, 3>& times) {
  // f(t) = [(x1-x0)(t), (x2-x0)(t), (x3-x0)(t)], a cubic k0 + k1 t + k2 t^2 + k3 t^3.
  const Eigen::Vector3d B0 = x[1] - x[0], C0 = x[2] - x[0], D0 = x[3] - x[0];
  const Eigen::Vector3d B1 = d[1] - d[0], C1 = d[2] - d[0], D1 = d[3] - d[0];
  const double k0 = triple(B0, C0, D0);
  const double k1 = triple(B1, C0, D0) + triple(B0, C1, D0) + triple(B0, C0, D1);
  const double k2 = triple(B1, C1, D0) + triple(B1, C0, D1) + triple(B0, C1, D1);
  const double k3 = triple(B1, C1, D1);
  const auto f = [&](double t) { return ((k3 * t + k2) * t + k1) * t + k0; };

  // Split [0, 1] at the roots of f' = k1 + 2 k2 t + 3 k3 t^2; f is monotone in between.
  std::array<double, 4> cuts{0.0, 1.0, 1.0, 1.0};
  int cut_count = 1;
  const double qa = 3.0 * k3, qb = 2.0 * k2, qc = k1;
  const double scale = std::abs(qa) + std::abs(qb) + std::abs(qc);
  if (std::abs(qa) > 1e-14 * scale) {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0) {
      const double sq = std::sqrt(disc);
      const double q = -0.5 * (qb + std::copysign(sq, qb));
      double r0 = q / qa, r1 = q != 0.0 ? qc / q : r0;
      if (r0 > r1) std::swap(r0, r1);
      for (double r : {r0, r1})
        if (r > 0.0 && r < 1.0) cuts[cut_count++] = r;
    }
  } else if (std::abs(qb) > 1e-14 * scale) {
    const double r = -qc / qb;
    if (r > 0.0 && r < 1.0) cuts[cut_count++] = r;
  }
  cuts[cut_count++] = 1.0;

  int count = 0;
  for (int k = 0; k + 1 < cut_count; ++k) {
    double lo = cuts[k], hi = cuts[k + 1];
    double flo = f(lo), fhi = f(hi);
    if (flo == 0.0) {
      if (count == 0 || times[count - 1] < lo) times[count++] = lo;
      continue;
    }
    if (flo * fhi > 0.0) continue;
    for (int it = 0; it < 60 && hi - lo > 1e-12; ++it) {
      const double mid = 0.5 * (lo + hi), fm = f(mid);
      if ((fm < 0.0) == (flo < 0.0)) {
        lo = mid;
        flo = fm;
      } else {
        hi = mid;
      }
    }
    if (count < 3) times[count++] = hi;
  }
  return count;
}

}  // namespace shellflow::cloth
