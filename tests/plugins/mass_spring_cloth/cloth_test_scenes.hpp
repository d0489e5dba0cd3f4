#pragma once
// Small cloth set-ups shared by the mass_spring_cloth tests.

#include <memory>

#include "mass_spring_cloth/cloth_simulator.hpp"
#include "shellflow/geometry/mesh_generators.hpp"

namespace shellflow::cloth::testing {

inline const Eigen::Vector3d kGravity(0.0, -9.81, 0.0);

/// A width x height grid hanging in the x-y plane (top edge at y = height / 2).
inline geometry::SurfaceMesh hanging_grid(double width, double height, int nu, int nv) {
  return geometry::make_grid(width, height, nu, nv, geometry::GridPattern::Herringbone);
}

inline std::unique_ptr<ClothSimulator> make_simulator(const geometry::SurfaceMesh& mesh,
                                                      const ClothMaterial& material,
                                                      const SolverSettings& solver,
                                                      const CollisionSettings& collision) {
  return std::make_unique<ClothSimulator>(
      build_cloth_model(mesh.positions, mesh.triangles, material), solver, collision, kGravity);
}

}  // namespace shellflow::cloth::testing
