// The water fraction F on cut cells (issue #52, docs/cut-cells.md §2.7): each part of a cell a
// level plate cuts holds its own water and moves it through its fragments. In a tank cut by a
// plate, a flow without divergence in any part (the projection on parts of a random one)
// carries F for 40 steps: the water is kept to round-off (F's lower bound raises nothing),
// water under the plate never reaches the parts or cells above it, and a film on the
// plate's far side from the centres (the extra parts) stays on that side.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grid_fluid_test_support.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/pressure/cut_cell_system.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/volume_fraction.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

const grid::UniformGrid kGrid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(8, 16, 8));
const double kDx = kGrid.dx();
const double kPlate = 5.82 * kDx;  // 0.32 of a cell above row 5's centres: the extras lie above

struct Tank {
  Tank()
      : cut(kGrid, {test::make_plate({0.25, kPlate, 0.25}, Eigen::Vector3d::UnitY(), 2.0, 9)}),
        parts(cut.parts),
        mac(kGrid) {
    fragments = parts.still_fragments();
    // A random flow projected on the parts of a full tank: no part has any divergence.
    const std::vector<double> full_cells(kGrid.size(Location::Cell), -1.0);
    const std::vector<double> full_parts(parts.parts().size(), -1.0);
    system.build(kGrid, parts, DomainBoundary(), {full_cells, full_parts});
    test::random_flow(mac, fragments, 0.5, 3);
    test::project_on_parts(system, mac, fragments);
  }
  test::CutShells cut;
  const CellParts& parts;
  FragmentVelocities fragments;
  CutCellSystem system;
  MacGrid mac;
};

/// F carried over `steps` steps of a Courant number ½ of the fastest face or fragment.
void carry(const Tank& tank, VolumeFraction& fraction, const LevelSet& level_set, int steps) {
  double fastest = tank.mac.max_face_speed();
  for (const auto& list : tank.fragments)
    for (const double w : list) fastest = std::max(fastest, std::abs(w));
  const double dt = 0.5 * kDx / fastest;
  for (int s = 0; s < steps; ++s) fraction.advect(tank.mac, level_set, dt, fastest);
}

// Water fills the tank under the plate (the slot parts of row 5 to their volume); above it is
// dry. Forty steps later nothing is above the plate (the parts above it and the cells of rows 6
// up hold no water: it has no fragment to cross), and the water is kept to 1e-12 of it.
TEST(CutCellFraction, WaterUnderAPlateNeverReachesItsOtherSide) {
  const Tank tank;
  LevelSet level_set(kGrid, 6.0 * kDx);
  for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c)
    level_set.phi()[c] = kGrid.position(Location::Cell, c).y() - kPlate;
  VolumeFraction fraction(level_set);
  for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c)
    fraction.values()[c] = kGrid.coordinates(Location::Cell, c).y() < 5 ? 1.0 : 0.0;
  fraction.set_cut_cells(&tank.parts, &tank.fragments);
  for (const CellPart& part : tank.parts.parts())
    if (part.slot) fraction.values()[part.cell] = part.volume;  // below the plate
  const double before = fraction.volume();
  carry(tank, fraction, level_set, 40);
  EXPECT_NEAR(fraction.volume(), before, 1e-12 * before);
  EXPECT_LE(std::abs(fraction.clipped_total()), 1e-12 * before);  // no part gave what it lacked
  for (size_t p = 0; p < tank.parts.parts().size(); ++p)
    if (!tank.parts.parts()[p].slot) {
      EXPECT_EQ(fraction.part_values()[p], 0.0) << "part " << p;
    }
  for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c)
    if (kGrid.coordinates(Location::Cell, c).y() > 5) {
      EXPECT_EQ(fraction.values()[c], 0.0);
    }
}

// A film 0.1 of a cell thick on the plate over part of it (the extra parts above the plate,
// whose cells' centres lie below it) and nothing else: forty steps of the flow keep its water
// to 1e-12 of it, and none of it ever gets below the plate
// (the slot parts of row 5 and the rows under it stay dry).
TEST(CutCellFraction, AFilmOnAPlatesFarSideStaysThereAndKeepsItsWater) {
  const Tank tank;
  LevelSet level_set(kGrid, 6.0 * kDx);
  for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c) level_set.phi()[c] = 1.0;
  VolumeFraction fraction(level_set);
  fraction.set_cut_cells(&tank.parts, &tank.fragments);
  for (size_t p = 0; p < tank.parts.parts().size(); ++p) {
    const CellPart& part = tank.parts.parts()[p];
    const Eigen::Vector3i c = kGrid.coordinates(Location::Cell, part.cell);
    if (!part.slot && c.x() >= 2 && c.x() < 6 && c.z() >= 2 && c.z() < 6)
      fraction.part_values()[p] = 0.1;
  }
  const double before = fraction.volume();
  ASSERT_NEAR(before, 16 * 0.1 * kDx * kDx * kDx, 1e-15);
  carry(tank, fraction, level_set, 40);
  EXPECT_NEAR(fraction.volume(), before, 1e-12 * before);
  EXPECT_LE(std::abs(fraction.clipped_total()), 1e-12 * before);  // no part gave what it lacked
  for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c)
    if (kGrid.coordinates(Location::Cell, c).y() <= 5) {
      EXPECT_EQ(fraction.values()[c], 0.0);
    }
}

}  // namespace
}  // namespace shellflow::grid_fluid
