#include "shellflow/bullet_rigid/shell_mass_properties.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::bullet_rigid {

ShellMassProperties shell_mass_properties(const sdk::Positions& positions,
                                          const sdk::Triangles& triangles,
                                          const Eigen::VectorXd& surface_density) {
  if (surface_density.size() != triangles.rows())
    throw Error("shell_mass_properties: " + std::to_string(surface_density.size()) +
                " surface densities for " + std::to_string(triangles.rows()) + " triangles");

  // Moments about the origin of the positions' frame, summed triangle by triangle:
  // mass, first moment ∫ρ x dA and second moment ∫ρ x xᵀ dA (exact for flat triangles).
  double area = 0.0;
  double mass = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::Vector3d a = positions.row(triangles(t, 0)).transpose();
    const Eigen::Vector3d b = positions.row(triangles(t, 1)).transpose();
    const Eigen::Vector3d c = positions.row(triangles(t, 2)).transpose();
    const double triangle_area = 0.5 * (b - a).cross(c - a).norm();
    const double m = surface_density[t] * triangle_area;
    const Eigen::Vector3d s = a + b + c;
    area += triangle_area;
    mass += m;
    first += (m / 3.0) * s;
    // A/12 (a aᵀ + b bᵀ + c cᵀ + s sᵀ): the second moment of a triangle of area A.
    second += (m / 12.0) *
              (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  if (!(area > 0.0))
    throw Error("shell_mass_properties: the mesh has zero area (" +
                std::to_string(triangles.rows()) + " triangles); a rigid shell needs triangles");
  if (!(mass > 0.0))
    throw Error("shell_mass_properties: the shell's mass is " + std::to_string(mass) +
                " kg; give it a positive surface density");

  ShellMassProperties p;
  p.area = area;
  p.mass = mass;
  p.centre_of_mass = first / mass;
  // Parallel-axis shift of the second moment to the centre of mass, then I = tr(S) Id − S.
  Eigen::Matrix3d s_com = second - mass * p.centre_of_mass * p.centre_of_mass.transpose();
  s_com = 0.5 * (s_com + s_com.transpose());
  p.inertia = s_com.trace() * Eigen::Matrix3d::Identity() - s_com;

  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(p.inertia);
  p.principal_moments = eigen.eigenvalues();
  p.principal_axes = eigen.eigenvectors();
  if (p.principal_axes.determinant() < 0.0) p.principal_axes.col(2) *= -1.0;
  return p;
}

ShellMassProperties shell_mass_properties(const sdk::Positions& positions,
                                          const sdk::Triangles& triangles, double surface_density) {
  return shell_mass_properties(positions, triangles,
                               Eigen::VectorXd::Constant(triangles.rows(), surface_density));
}

}  // namespace shellflow::bullet_rigid
