#include "shellflow/bullet_rigid/fluid_wrench.hpp"

#include <Eigen/Geometry>
#include <string>

#include "shellflow/sdk/error.hpp"

namespace shellflow::bullet_rigid {

Wrench sum_triangle_forces(const sdk::Positions& positions, const sdk::Triangles& triangles,
                           const sdk::TriangleVectors& forces,
                           const Eigen::Vector3d& centre_of_mass) {
  Wrench w;
  if (forces.rows() == 0) return w;
  if (forces.rows() != triangles.rows())
    throw Error("rigid shell: " + std::to_string(forces.rows()) + " triangle forces for " +
                std::to_string(triangles.rows()) +
                " triangles; the fluid must give one force per triangle of the surface");
  // §5.1: "the force and torque are accumulated by accounting for all the triangles",
  // each triangle's net force acting at its barycentre. A plain ordered loop, so the sum
  // (and a look-ahead that repeats it) is reproducible bit for bit.
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::Vector3d f = forces.row(t).transpose();
    const Eigen::Vector3d barycentre =
        (positions.row(triangles(t, 0)) + positions.row(triangles(t, 1)) +
         positions.row(triangles(t, 2)))
            .transpose() /
        3.0;
    w.force += f;
    w.torque += (barycentre - centre_of_mass).cross(f);
  }
  return w;
}

}  // namespace shellflow::bullet_rigid
