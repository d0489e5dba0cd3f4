#include "grid_fluid_test_support.hpp"

#include <Eigen/Geometry>
#include <memory>

namespace shellflow::grid_fluid::test {

sdk::ShellSurface make_plate(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                             double size, int nodes) {
  auto mesh = geometry::make_grid(size, size, nodes, nodes, geometry::GridPattern::Alternating);
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal);
  sdk::ShellSurface s;
  s.name = "plate";
  s.positions = mesh.positions;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    s.positions.row(i) = (center + q * s.positions.row(i).transpose()).transpose();
  s.velocities = sdk::Positions::Zero(s.positions.rows(), 3);
  s.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  s.surface_density = Eigen::VectorXd::Ones(mesh.triangles.rows());
  return s;
}

}  // namespace shellflow::grid_fluid::test
