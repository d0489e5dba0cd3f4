// The water a scene starts with (water/initial_water): a closed mesh's inside is found by
// the parity of its crossings along each grid row, which must hold when the rows run
// exactly through the mesh's edges and vertices, as they do whenever a mesh's vertices
// sit on the grid.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "grid_fluid_test_support.hpp"
#include "shellflow/grid_fluid/water/initial_water.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

struct Placement {
  Eigen::Vector3d axis;
  double degrees;
};

class MeshInitialWater : public ::testing::TestWithParam<Placement> {};

TEST_P(MeshInitialWater, IsTheInsideOfABoxWhoseEdgesLieOnNodeRows) {
  // A box mesh 12 × 2 × 16 cells (the divisions put its vertices on node rows), centred on
  // a node, turned about the axis: every node's φ is the box's exact signed distance
  // within the band (the closest point is exact; its sign from the crossings).
  const int n = 32;
  const double dx = 1.0 / n;
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), dx, Eigen::Vector3i::Constant(n));
  const Placement placement = GetParam();
  const Eigen::Vector3d size(12 * dx, 2 * dx, 16 * dx), centre(0.5, 0.5, 0.5);
  const nlohmann::json entries = {
      {{"type", "mesh"},
       {"subtract", false},
       {"mesh", {{"type", "box"}, {"size", {size.x(), size.y(), size.z()}}, {"divisions", 4}}},
       {"transform",
        {{"rotate_axis", {placement.axis.x(), placement.axis.y(), placement.axis.z()}},
         {"rotate_deg", placement.degrees},
         {"translate", {centre.x(), centre.y(), centre.z()}}}}}};
  const double band = 4.0 * dx;
  LevelSet level_set(grid, band);
  fill_initial_water(entries, Eigen::Vector3d::UnitY(), "/water/initial", level_set);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(placement.degrees * M_PI / 180.0, placement.axis.normalized())
          .toRotationMatrix();
  int inside = 0, wrong = 0;
  for (std::int64_t i = 0; i < grid.size(Location::Node); ++i) {
    const Eigen::Vector3d q = r.transpose() * (grid.position(Location::Node, i) - centre);
    const Eigen::Vector3d out = q.cwiseAbs() - 0.5 * size;
    const double exact = std::min(out.maxCoeff(), 0.0) + out.cwiseMax(0.0).norm();
    const double phi = level_set.phi()[i];
    if (std::abs(exact) < 1e-9 || std::abs(exact) >= band) continue;  // on it; beyond the band
    inside += exact < 0.0 ? 1 : 0;
    // Round-off of the closest point; a wrong sign is off by 2|d| > 1e-9.
    if (std::abs(phi - exact) > 1e-9) ++wrong;
    EXPECT_NEAR(phi, exact, 1e-9) << "node " << grid.coordinates(Location::Node, i).transpose();
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(inside, 100);  // not vacuous: the box holds nodes
}

INSTANTIATE_TEST_SUITE_P(Turned, MeshInitialWater,
                         ::testing::Values(Placement{Eigen::Vector3d::UnitZ(), 0.0},
                                           Placement{-Eigen::Vector3d::UnitZ(), 20.0},
                                           Placement{Eigen::Vector3d::UnitX(), 90.0},
                                           Placement{Eigen::Vector3d(1, 1, 1), 30.0}));

}  // namespace
}  // namespace shellflow::grid_fluid
