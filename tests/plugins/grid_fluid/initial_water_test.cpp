// The water a scene starts with (water/initial_water): a closed mesh's inside is found by
// the parity of its crossings along each grid row, which must hold when the rows run
// exactly through the mesh's edges and vertices, as they do whenever a mesh's vertices
// sit on the grid. An entry that fills no cell of the domain is refused by name.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "grid_fluid_test_support.hpp"
#include "shellflow/grid_fluid/water/initial_water.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;
using ::testing::HasSubstr;

struct Placement {
  Eigen::Vector3d axis;
  double degrees;
};

class MeshInitialWater : public ::testing::TestWithParam<Placement> {};

TEST_P(MeshInitialWater, IsTheInsideOfABoxWhoseEdgesLieOnRowsOfSamples) {
  // A box mesh 12 × 2 × 16 cells (the divisions put its vertices on rows of φ's samples, the
  // cell centres), centred on a sample, turned about the axis: every sample's φ is the box's
  // exact signed distance within the band (the closest point is exact; its sign from the
  // crossings).
  const int n = 32;
  const double dx = 1.0 / n;
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), dx, Eigen::Vector3i::Constant(n));
  const double band = 4.0 * dx;
  LevelSet level_set(grid, band);
  const grid::UniformGrid& lattice = level_set.grid();
  const Placement placement = GetParam();
  const Eigen::Vector3d size(12 * dx, 2 * dx, 16 * dx),
      centre = lattice.position(Location::Node, Eigen::Vector3i::Constant(n / 2 - 1));
  const nlohmann::json entries = {
      {{"type", "mesh"},
       {"subtract", false},
       {"mesh", {{"type", "box"}, {"size", {size.x(), size.y(), size.z()}}, {"divisions", 4}}},
       {"transform",
        {{"rotate_axis", {placement.axis.x(), placement.axis.y(), placement.axis.z()}},
         {"rotate_deg", placement.degrees},
         {"translate", {centre.x(), centre.y(), centre.z()}}}}}};
  fill_initial_water(entries, Eigen::Vector3d::UnitY(), "/water/initial", level_set);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(placement.degrees * M_PI / 180.0, placement.axis.normalized())
          .toRotationMatrix();
  int inside = 0, wrong = 0;
  for (std::int64_t i = 0; i < lattice.size(Location::Node); ++i) {
    const Eigen::Vector3d q = r.transpose() * (lattice.position(Location::Node, i) - centre);
    const Eigen::Vector3d out = q.cwiseAbs() - 0.5 * size;
    const double exact = std::min(out.maxCoeff(), 0.0) + out.cwiseMax(0.0).norm();
    const double phi = level_set.phi()[i];
    if (std::abs(exact) < 1e-9 || std::abs(exact) >= band) continue;  // on it; beyond the band
    inside += exact < 0.0 ? 1 : 0;
    // Round-off of the closest point; a wrong sign is off by 2|d| > 1e-9.
    if (std::abs(phi - exact) > 1e-9) ++wrong;
    EXPECT_NEAR(phi, exact, 1e-9) << "sample "
                                  << lattice.coordinates(Location::Node, i).transpose();
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(inside, 100);  // not vacuous: the box holds samples
}

INSTANTIATE_TEST_SUITE_P(Turned, MeshInitialWater,
                         ::testing::Values(Placement{Eigen::Vector3d::UnitZ(), 0.0},
                                           Placement{-Eigen::Vector3d::UnitZ(), 20.0},
                                           Placement{Eigen::Vector3d::UnitX(), 90.0},
                                           Placement{Eigen::Vector3d(1, 1, 1), 30.0}));

/// A water scene in the schema's default domain [0, 1]³ at 8 cells (Δx = 1/8 exactly):
/// enough to build the level set, quick to.
nlohmann::json water_at_8(nlohmann::json initial) {
  return {{"resolution", 8}, {"water", {{"initial", std::move(initial)}}}};
}

TEST(InitialWater, AnEntryThatFillsNoCellIsRefusedNamingItsPath) {
  // Each entry lies wholly outside the domain or only touches a face, so it would fill (or
  // carve) no cell: validate refuses it at its own path, after a valid pool at /0, with
  // its extent and the domain's.
  const nlohmann::json pool = {{"type", "pool"}, {"height", 0.5}};
  const std::vector<std::pair<nlohmann::json, std::string>> cases = {
      {{{"type", "box"}, {"min", {2, 0, 0}}, {"max", {3, 1, 1}}}, "the box [(2, 0, 0), (3, 1, 1)]"},
      // Its face on the domain's x = 0 face: no volume shared.
      {{{"type", "box"}, {"min", {-1, 0, 0}}, {"max", {0, 1, 1}}},
       "the box [(-1, 0, 0), (0, 1, 1)]"},
      // Its bounding box overlaps the domain's corner (1, 1, 1); the ball, 0.35 from it,
      // does not.
      {{{"type", "sphere"}, {"center", {1.2, 1.2, 1.2}}, {"radius", 0.3}},
       "the sphere (bounds [(0.9, 0.9, 0.9), (1.5, 1.5, 1.5)])"},
      {{{"type", "cylinder"}, {"from", {0.5, 2, 0.5}}, {"to", {0.5, 3, 0.5}}, {"radius", 0.1}},
       "the cylinder (bounds [(0.4, 1.9, 0.4), (0.6, 3.1, 0.6)])"},
      // Water below y = 0 (up = −gravity = +y): its surface on the floor.
      {{{"type", "pool"}, {"height", 0.0}},
       "the pool (water where x·up < 0; x·up spans [0, 1] over the domain, up = (0, 1, 0))"},
      {{{"type", "mesh"},
        {"mesh", {{"type", "box"}, {"size", {0.2, 0.2, 0.2}}}},
        {"transform", {{"translate", {0.5, -0.5, 0.5}}}}},
       "the mesh, transformed (bounds [(0.4, -0.6, 0.4), (0.6, -0.4, 0.6)])"},
  };
  const std::string path = std::string(test::kRefusedScene) + ": /fluid/water/initial/1: ";
  const std::string domain = " lies entirely outside the domain [(0, 0, 0), (1, 1, 1)], so it ";
  for (const auto& [entry, shape] : cases) {
    SCOPED_TRACE(entry.dump());
    const std::string message = test::validate_refusal(water_at_8({pool, entry}));
    EXPECT_THAT(message, HasSubstr(path));
    EXPECT_THAT(message, HasSubstr(shape + domain + "would add no water"));
  }
  // A subtracted entry outside carves nothing out.
  nlohmann::json carve = cases[0].first;
  carve["subtract"] = true;
  const std::string message = test::validate_refusal(water_at_8({pool, carve}));
  EXPECT_THAT(message, HasSubstr(path));
  EXPECT_THAT(message, HasSubstr(cases[0].second + domain + "would remove no water"));
}

TEST(InitialWater, AnEntryPartlyOutsideTheDomainIsAcceptedAndHoldsWater) {
  // Partly outside is how a column against a wall is written (the dam break's box from
  // −1); a ball centred on a corner and a pool above the lid are inside in part too.
  const std::vector<nlohmann::json> entries = {
      {{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.25, 0.5, 1}}},
      {{"type", "sphere"}, {"center", {1, 1, 1}}, {"radius", 0.3}},
      {{"type", "pool"}, {"height", 2.0}},
      {{"type", "cylinder"}, {"from", {0.5, -1, 0.5}}, {"to", {0.5, 0.5, 0.5}}, {"radius", 0.2}},
      {{"type", "mesh"},
       {"mesh", {{"type", "box"}, {"size", {0.5, 0.5, 0.5}}}},
       {"transform", {{"translate", {0, 0.5, 0.5}}}}},
  };
  for (const auto& entry : entries) {
    SCOPED_TRACE(entry.dump());
    std::unique_ptr<GridFluid> fluid;
    ASSERT_NO_THROW(fluid = test::make_fluid(water_at_8({entry})));
    EXPECT_GT(fluid->liquid()->level_set().volume(), 0.0);  // the part inside is there
  }
}

}  // namespace
}  // namespace shellflow::grid_fluid
