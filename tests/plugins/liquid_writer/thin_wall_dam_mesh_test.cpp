// The liquid mesh of grid_fluid's thin-wall dam (configs/verify/water_thin_wall_dam.json
// at 16^3): a tank split by a static plate at x = 0.5 + Δx/3, water on the −x side. The
// water is filled to x = 0.55, past the plate, as a careless initial box would: φ's zero
// crossing lies behind the plate. After 0.5 s of simulation, the
// mesh of the fluid's own φ (without the plate) bridges it; with the plate, no triangle
// meets it (exact: counts), and on the level set alone every vertex is on the wet side. A
// volume fraction keeps the sliver the box put behind the plate as water, which runs down
// the dry side: there the mesh shows it apart from the wet side.

#include <gtest/gtest.h>

#include "../grid_fluid/grid_fluid_test_support.hpp"
#include "mesh_checks.hpp"
#include "shellflow/liquid_writer/liquid_mesher.hpp"

namespace shellflow::liquid_writer {
namespace {

/// On each water core (grid_fluid::test::water_core): the level set alone (whose mesh closes
/// on the walls through ghost layers) and with a volume fraction (the default).
class ThinWallDamMesh : public ::testing::TestWithParam<const char*> {};

INSTANTIATE_TEST_SUITE_P(Layouts, ThinWallDamMesh, ::testing::Values("cells", "fraction"),
                         [](const auto& info) { return std::string(info.param); });

TEST_P(ThinWallDamMesh, NoTriangleJoinsTheWetSideToTheDrySide) {
  auto fluid = grid_fluid::test::make_fluid(
      {{"resolution", 16},
       {"pressure", {{"tolerance", 1e-6}}},
       {"water",
        grid_fluid::test::water_core(
            GetParam(),
            {{"initial", {{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.55, 0.8, 2}}}}}})}});
  const double dx = fluid->grid().dx();
  const double plate_x = 0.5 + dx / 3.0;
  const sdk::ShellSurface plate =
      grid_fluid::test::make_plate({plate_x, 0.5, 0.5}, Eigen::Vector3d::UnitX(), 1.2, 9);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v_eff{plate.velocities};
  double t = 0.0;
  while (t < 0.5 - 1e-12) {
    const double dt = std::min(fluid->stable_dt(0.9), 0.5 - t);
    fluid->advect(t, dt, shells, shells);
    fluid->project(dt, shells, v_eff);
    t += dt;
  }
  const auto fields = fluid->fields();
  const auto phi =
      std::find_if(fields.begin(), fields.end(), [](auto& f) { return f.name == "phi"; });
  const auto velocity =
      std::find_if(fields.begin(), fields.end(), [](auto& f) { return f.name == "velocity"; });
  ASSERT_NE(phi, fields.end());
  ASSERT_NE(velocity, fields.end());

  const LiquidMesh bridging = mesh_liquid(*phi, &*velocity, {}, {});
  EXPECT_GT(testing::triangles_meeting_shell(bridging.positions, bridging.triangles, plate), 0)
      << "the fluid's φ no longer bridges the plate: this test would prove nothing";

  for (const double adaptivity : {0.0, 0.5}) {
    LiquidMeshOptions options;
    options.adaptivity = adaptivity;
    const LiquidMesh mesh = mesh_liquid(*phi, &*velocity, shells, options);
    ASSERT_GT(mesh.triangles.rows(), 100);
    EXPECT_EQ(testing::triangles_meeting_shell(mesh.positions, mesh.triangles, plate), 0)
        << "adaptivity " << adaptivity;
    if (std::string(GetParam()) != "fraction") {
      EXPECT_LT(mesh.positions.col(0).maxCoeff(), plate_x) << "adaptivity " << adaptivity;
    }
    // The water ends within a cell of the plate: the touched cells' faces at 0.5.
    EXPECT_GT(mesh.positions.col(0).maxCoeff(), 0.5 - dx) << "adaptivity " << adaptivity;
    EXPECT_TRUE(testing::closed_and_consistently_wound(mesh.triangles));
  }
}

}  // namespace
}  // namespace shellflow::liquid_writer
