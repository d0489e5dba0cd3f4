#include "shellflow/preview_writer/water_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "shellflow/grid/uniform_grid.hpp"

namespace shellflow::preview_writer {

namespace {

// Refinement stops once |φ| or the bracket is below this fraction of dx: far below a pixel
// at any sensible camera distance, and above the round-off of φ (|φ| ~ dx, 1e-16 relative).
constexpr double kRefineTolerance = 1e-9;
// Illinois regula falsi converges superlinearly (order ≈ 1.44); 64 steps only bound a
// pathological φ.
constexpr int kMaxRefineSteps = 64;

}  // namespace

WaterSurface::WaterSurface(const sdk::FieldView& field) : m_field(field, "level set") {}

Eigen::Vector3d WaterSurface::gradient(const Eigen::Vector3d& x) const {
  const double h = m_field.dx();
  Eigen::Vector3d g;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d forward = x, backward = x;
    forward[a] += h;
    backward[a] -= h;
    g[a] = (m_field.value(forward) - m_field.value(backward)) / (2.0 * h);
  }
  return g;
}

void WaterSurface::see_shells(const ShellScene& scene) {
  m_scene = &scene;
  const std::array<int, 3> n = m_field.cells();
  const grid::UniformGrid cells(m_field.origin(), m_field.dx(), {n[0], n[1], n[2]});
  m_near_shell.assign(static_cast<size_t>(cells.size(grid::Location::Cell)), 0);
  // A cell a triangle may cut: its centre within half a cell of the triangle's box.
  std::vector<geometry::Aabb> boxes;
  scene.triangle_boxes(boxes);
  for (const geometry::Aabb& box : boxes) {
    const geometry::Aabb grown = box.inflated(0.5 * m_field.dx());
    const grid::IndexBox range =
        cells.samples_in_box(grid::Location::Cell, grown.lower, grown.upper);
    for (int k = range.lo.z(); k <= range.hi.z(); ++k)
      for (int j = range.lo.y(); j <= range.hi.y(); ++j)
        for (int i = range.lo.x(); i <= range.hi.x(); ++i)
          m_near_shell[cells.index(grid::Location::Cell, i, j, k)] = 1;
  }
}

double WaterSurface::phi_seen(const Eigen::Vector3d& x) const {
  const TrilinearField::Stencil st = m_field.stencil(x);
  if (m_scene == nullptr || m_near_shell[m_field.cell_index(st)] == 0) return m_field.value(st);
  const auto seen = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& node) {
    return !m_scene->first_hit(from, node - from, 1.0).hit();
  };
  return m_field.value_seen(st, x, seen, m_field.dx());
}

WaterHit WaterSurface::first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                 double max_distance, double h) const {
  double s_in = 0.0, s_out = 0.0;
  int entry_axis = -1;
  if (!m_field.clip(origin, direction, s_in, s_out, &entry_axis)) return {};
  const double begin = std::max(0.0, s_in);
  const double end = std::min(max_distance, s_out);
  if (!(begin <= end)) return {};
  auto phi_at = [&](double s) { return phi_seen(origin + s * direction); };

  WaterHit hit;
  double a = begin;
  double fa = phi_at(a);
  if (fa <= 0.0) {
    // Already in water where the segment starts: at a box face when the ray enters the box
    // there (the face's outward normal), else the eye is in the water (facing it).
    hit.distance = begin;
    hit.normal = -direction;
    if (s_in > 0.0 && entry_axis >= 0) {
      hit.normal = Eigen::Vector3d::Zero();
      hit.normal[entry_axis] = direction[entry_axis] > 0.0 ? -1.0 : 1.0;
    }
    return hit;
  }
  // March: the first sample with φ ≤ 0 closes the bracket [a, b] (φ(a) > 0 ≥ φ(b)).
  double b = a;
  double fb = fa;
  for (long n = 1;; ++n) {
    b = std::min(begin + static_cast<double>(n) * h, end);  // no drift from repeated sums
    fb = phi_at(b);
    if (fb <= 0.0) break;
    if (b >= end) return {};
    a = b;
    fa = fb;
  }
  // Regula falsi with the Illinois modification (Dowell & Jarratt 1971): the end point
  // kept twice in a row has its value halved, so both ends of the bracket move.
  const double tolerance = kRefineTolerance * m_field.dx();
  double s = b;
  int kept = 0;  // +1: a was kept last time, -1: b was
  for (int step = 0; step < kMaxRefineSteps && b - a > tolerance; ++step) {
    s = (a * fb - b * fa) / (fb - fa);  // fb - fa < 0: the secant's zero, inside [a, b]
    const double fs = phi_at(s);
    if (std::abs(fs) <= tolerance) break;
    if (fs < 0.0) {
      b = s;
      fb = fs;
      if (kept == +1) fa *= 0.5;
      kept = +1;
    } else {
      a = s;
      fa = fs;
      if (kept == -1) fb *= 0.5;
      kept = -1;
    }
    s = b;
  }
  hit.distance = s;
  const Eigen::Vector3d g = gradient(origin + s * direction);
  const double norm = g.norm();
  hit.normal = norm > 0.0 ? Eigen::Vector3d(g / norm) : Eigen::Vector3d(-direction);
  return hit;
}

}  // namespace shellflow::preview_writer
