#pragma once
// Checks on triangle meshes for the liquid_writer tests: closedness, node-field views, and
// exact intersection of a mesh with a thin shell's triangles.

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <map>
#include <utility>
#include <vector>

#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::liquid_writer::testing {

/// A grid field owned by a test, shown as an sdk::FieldView: node samples unless
/// `location` says they are cell centres.
struct NodeGrid {
  sdk::FieldView::Location location = sdk::FieldView::Location::Node;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double dx = 1.0;
  std::array<int, 3> dims{0, 0, 0};
  std::array<std::vector<double>, 3> data;

  NodeGrid(const Eigen::Vector3d& o, double h, std::array<int, 3> n, int components)
      : origin(o), dx(h), dims(n) {
    for (int c = 0; c < components; ++c)
      data[c].assign(static_cast<size_t>(n[0]) * n[1] * n[2], 0.0);
  }
  template <class F>
  void fill(int c, F&& f) {
    size_t s = 0;
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) data[c][s++] = f(origin + dx * Eigen::Vector3d(i, j, k));
  }
  sdk::FieldView view(const std::string& name) const {
    sdk::FieldView v;
    v.name = name;
    v.location = location;
    v.origin = origin;
    v.dx = dx;
    v.dims = dims;
    v.components = data[1].empty() ? 1 : 3;
    for (int c = 0; c < v.components; ++c) v.data[c] = data[c].data();
    return v;
  }
};

/// Every edge is shared by exactly two triangles that run it in opposite directions: a
/// closed, consistently wound surface.
inline bool closed_and_consistently_wound(const sdk::Triangles& triangles) {
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int e = 0; e < 3; ++e) ++directed[{triangles(t, e), triangles(t, (e + 1) % 3)}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return !directed.empty();
}

/// Does the closed segment [p, q] meet the closed triangle (a, b, c)? Exact up to
/// round-off (Möller–Trumbore with the boundaries included).
inline bool segment_meets_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                                   const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                   const Eigen::Vector3d& c) {
  const Eigen::Vector3d d = q - p, e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return false;  // parallel: a coplanar touch is not a crossing here
  const Eigen::Vector3d s = p - a;
  const double u = s.dot(h) / det;
  if (u < 0.0 || u > 1.0) return false;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = d.dot(qv) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = e2.dot(qv) / det;
  return t >= 0.0 && t <= 1.0;
}

/// Do two triangles intersect? (Non-coplanar triangles meet iff an edge of one meets the
/// other.)
inline bool triangles_intersect(const std::array<Eigen::Vector3d, 3>& x,
                                const std::array<Eigen::Vector3d, 3>& y) {
  for (int e = 0; e < 3; ++e) {
    if (segment_meets_triangle(x[e], x[(e + 1) % 3], y[0], y[1], y[2])) return true;
    if (segment_meets_triangle(y[e], y[(e + 1) % 3], x[0], x[1], x[2])) return true;
  }
  return false;
}

/// Triangles of the mesh that meet a triangle of `shell`.
inline int triangles_meeting_shell(const sdk::Positions& positions, const sdk::Triangles& triangles,
                                   const sdk::ShellSurface& shell) {
  int meeting = 0;
  const sdk::Triangles& st = *shell.triangles;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    std::array<Eigen::Vector3d, 3> x;
    for (int c = 0; c < 3; ++c) x[c] = positions.row(triangles(t, c)).transpose();
    for (Eigen::Index u = 0; u < st.rows(); ++u) {
      std::array<Eigen::Vector3d, 3> y;
      for (int c = 0; c < 3; ++c) y[c] = shell.positions.row(st(u, c)).transpose();
      if (triangles_intersect(x, y)) {
        ++meeting;
        break;
      }
    }
  }
  return meeting;
}

}  // namespace shellflow::liquid_writer::testing
