// Per-triangle fluid forces summed into a force and a torque about the centre of mass
// (§5.1, Guendelman et al. 2005).
#include "shellflow/bullet_rigid/fluid_wrench.hpp"

#include <gtest/gtest.h>

#include "shellflow/bullet_rigid/shell_mass_properties.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::bullet_rigid {
namespace {

/// Uniform pressure p on every triangle, along the triangle's (outward) normal:
/// f_t = p A_t n_t = p/2 (b − a) × (c − a).
sdk::TriangleVectors uniform_pressure(const geometry::SurfaceMesh& mesh, double p) {
  sdk::TriangleVectors f(mesh.triangles.rows(), 3);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(t, 0)).transpose();
    const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(t, 1)).transpose();
    const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(t, 2)).transpose();
    f.row(t) = (0.5 * p * (b - a).cross(c - a)).transpose();
  }
  return f;
}

double total_area(const geometry::SurfaceMesh& mesh) {
  return shell_mass_properties(mesh.positions, mesh.triangles, 1.0).area;
}

TEST(FluidWrench, UniformPressureOnAClosedShellGivesNoForceAndNoTorque) {
  // ∮ p n dA = 0 and ∮ x × p n dA = 0 over any closed surface (divergence theorem); for
  // flat triangles with the force at the barycentre the discrete sums are the exact
  // integrals over the polyhedron, so they vanish up to round-off: a sum of N terms of
  // size p·A_t cancels to ≲ 1e-13 p·A (N ≤ 5120 here, ε = 1.1e-16).
  const double p = 250.0;  // [Pa]
  for (const auto& mesh : {geometry::make_sphere(0.4, 4), geometry::make_box({0.5, 0.3, 0.2}, 3)}) {
    // Off the origin, so the torque arm is not trivially small.
    auto moved = mesh;
    geometry::apply_transform(Eigen::Affine3d(Eigen::Translation3d(1.0, 2.0, -0.5)), moved);
    const auto mass = shell_mass_properties(moved.positions, moved.triangles, 1.0);
    const Wrench w = sum_triangle_forces(moved.positions, moved.triangles,
                                         uniform_pressure(moved, p), mass.centre_of_mass);
    const double scale = p * total_area(moved);
    EXPECT_LT(w.force.norm(), 1e-13 * scale);
    EXPECT_LT(w.torque.norm(), 1e-13 * scale);
  }
}

TEST(FluidWrench, UniformPressureOnAnOpenBoxLacksTheLidsForce) {
  // The same pressure on the cup (no +y face) sums to minus what the lid would carry:
  // F = −p a c ŷ. The lid's barycentre lies on the y axis through the centre of mass, so
  // the torque still vanishes. (Shows the closed-shell test above can fail.)
  const double p = 250.0, a = 0.6, b = 0.4, c = 0.3;
  const auto cup = geometry::make_open_box({a, b, c}, 3);
  const auto mass = shell_mass_properties(cup.positions, cup.triangles, 1.0);
  const Wrench w = sum_triangle_forces(cup.positions, cup.triangles, uniform_pressure(cup, p),
                                       mass.centre_of_mass);
  const double scale = p * total_area(cup);
  EXPECT_LT((w.force - Eigen::Vector3d(0, -p * a * c, 0)).norm(), 1e-13 * scale);
  EXPECT_LT(w.torque.norm(), 1e-13 * scale);
}

TEST(FluidWrench, OneForceActsAtItsTrianglesBarycentre) {
  const auto mesh = geometry::make_box({0.5, 0.3, 0.2}, 1);
  const Eigen::Vector3d centre(0.1, -0.2, 0.05);  // any reference point
  sdk::TriangleVectors f = sdk::TriangleVectors::Zero(mesh.triangles.rows(), 3);
  const int t = 5;
  const Eigen::Vector3d force(3.0, -1.0, 2.0);
  f.row(t) = force.transpose();
  const Eigen::Vector3d barycentre =
      (mesh.positions.row(mesh.triangles(t, 0)) + mesh.positions.row(mesh.triangles(t, 1)) +
       mesh.positions.row(mesh.triangles(t, 2)))
          .transpose() /
      3.0;
  const Wrench w = sum_triangle_forces(mesh.positions, mesh.triangles, f, centre);
  // A single term: exact up to one rounding per operation (1e-15 at these magnitudes).
  EXPECT_LT((w.force - force).norm(), 1e-15);
  EXPECT_LT((w.torque - (barycentre - centre).cross(force)).norm(), 1e-14);
}

TEST(FluidWrench, EmptyForcesGiveZeroAndWrongSizesThrow) {
  const auto mesh = geometry::make_box({1, 1, 1}, 1);
  const Wrench w = sum_triangle_forces(mesh.positions, mesh.triangles, sdk::TriangleVectors(),
                                       Eigen::Vector3d::Zero());
  EXPECT_EQ(w.force, Eigen::Vector3d::Zero());
  EXPECT_EQ(w.torque, Eigen::Vector3d::Zero());
  EXPECT_THROW(sum_triangle_forces(mesh.positions, mesh.triangles, sdk::TriangleVectors::Zero(3, 3),
                                   Eigen::Vector3d::Zero()),
               Error);
}

}  // namespace
}  // namespace shellflow::bullet_rigid
