#include "mass_spring_cloth/cloth_model.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "shellflow/sdk/error.hpp"

namespace shellflow::cloth {

namespace {

struct EdgeRecord {
  int a, b;           // sorted node pair
  int triangle;       // adjacent triangle
  int opposite;       // its third node
  int first, second;  // the edge's nodes in the triangle's orientation
};

double cotangent(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return u.dot(v) / u.cross(v).norm();
}

}  // namespace

ClothModel build_cloth_model(const sdk::Positions& positions, const sdk::Triangles& triangles,
                             const ClothMaterial& material) {
  ClothModel model;
  const int n = static_cast<int>(positions.rows());
  model.rest_positions = Eigen::Map<const Eigen::VectorXd>(positions.data(), 3 * n);
  model.triangles = triangles;
  model.masses = Eigen::VectorXd::Zero(n);
  model.node_areas = Eigen::VectorXd::Zero(n);
  model.bending_stiffness = material.bending_stiffness;
  model.bending_damping = material.bending_damping;
  model.air_damping = material.air_damping;
  model.surface_density = material.surface_density;

  const auto X = [&](int k) -> Eigen::Vector3d { return positions.row(k).transpose(); };
  std::vector<double> areas(triangles.rows());
  std::vector<EdgeRecord> edges;
  edges.reserve(3 * triangles.rows());
  for (int t = 0; t < triangles.rows(); ++t) {
    const int v[3] = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
    for (int k = 0; k < 3; ++k)
      if (v[k] < 0 || v[k] >= n)
        throw Error("cloth mesh: triangle " + std::to_string(t) + " refers to node " +
                    std::to_string(v[k]) + " of " + std::to_string(n));
    const double area = 0.5 * (X(v[1]) - X(v[0])).cross(X(v[2]) - X(v[0])).norm();
    if (!(area > 0.0))
      throw Error("cloth mesh: triangle " + std::to_string(t) +
                  " has zero area; remove degenerate triangles from the mesh");
    areas[t] = area;
    for (int k = 0; k < 3; ++k) {
      // Lumped mass: a third of each triangle to each of its nodes.
      model.masses[v[k]] += material.surface_density * area / 3.0;
      model.node_areas[v[k]] += area / 3.0;
      const int p = v[(k + 1) % 3], q = v[(k + 2) % 3];
      edges.push_back({std::min(p, q), std::max(p, q), t, v[k], p, q});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeRecord& l, const EdgeRecord& r) {
    return l.a != r.a ? l.a < r.a : (l.b != r.b ? l.b < r.b : l.triangle < r.triangle);
  });

  std::vector<Spring> shear;
  for (size_t s = 0; s < edges.size();) {
    size_t e = s;
    while (e < edges.size() && edges[e].a == edges[s].a && edges[e].b == edges[s].b) ++e;
    const EdgeRecord& r0 = edges[s];
    double edge_area = 0.0;
    for (size_t k = s; k < e; ++k) edge_area += areas[edges[k].triangle];
    const double L0 = (X(r0.a) - X(r0.b)).norm();
    // Structural spring, (4/5) Y A_e / L0^2 (see the header for the calibration).
    model.springs.push_back({r0.a, r0.b, L0,
                             0.8 * material.stretch_stiffness * edge_area / (L0 * L0),
                             0.8 * material.stretch_damping * edge_area / (L0 * L0)});
    if (e - s == 2) {
      const EdgeRecord& r1 = edges[s + 1];
      const int c = r0.opposite, d = r1.opposite;
      const double Lcd = (X(c) - X(d)).norm();
      if (Lcd > 0.0)
        shear.push_back({c, d, Lcd, material.shear_stiffness * edge_area / (Lcd * Lcd),
                         material.shear_damping * edge_area / (Lcd * Lcd)});
      // Bending stencil, Bergou et al. 2006: a, b the edge (in triangle 0's orientation).
      const int a = r0.first, b = r0.second;
      const Eigen::Vector3d xa = X(a), xb = X(b), xc = X(c), xd = X(d);
      const double cot_a1 = cotangent(xb - xa, xc - xa), cot_b1 = cotangent(xa - xb, xc - xb);
      const double cot_a2 = cotangent(xb - xa, xd - xa), cot_b2 = cotangent(xa - xb, xd - xb);
      BendingStencil stencil;
      stencil.nodes = {a, b, c, d};
      stencil.weights = {cot_b1 + cot_b2, cot_a1 + cot_a2, -(cot_a1 + cot_b1), -(cot_a2 + cot_b2)};
      stencil.inverse_area = 1.0 / edge_area;
      model.bending.push_back(stencil);
    }
    s = e;
  }
  model.structural_count = static_cast<int>(model.springs.size());
  model.springs.insert(model.springs.end(), shear.begin(), shear.end());
  return model;
}

}  // namespace shellflow::cloth
