// CutCellSystem: the projection's system on cut cells (issue #52, docs/cut-cells.md §2.4).
// Known answers: still water on both sides of a level plate stays still, and the part of a
// cut cell beyond the plate from its centre (a virtual node) carries the hydrostatic pressure
// of its own side at the centre, wherever the plate lies in the cell; a random flow projected
// in a full tank cut by plates leaves every part without divergence and loses kinetic energy
// (the projection is orthogonal in the apertures' norm).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grid_fluid_test_support.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/pressure/cut_cell_system.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

// A closed tank 0.5 x 1 x 0.5 m at Δx = 1/16 m.
const grid::UniformGrid kGrid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(8, 16, 8));
const double kDx = kGrid.dx();
constexpr double kGravity = 9.81, kDt = 0.01;

// Water fills the tank below a level plate across it and stands 2.7 cells deep on it. One
// step of gravity (u* = −g Δt on every y face and fragment) is taken back entirely by the
// pressure: every face and fragment with water on a side is still to 1e-9 m/s (the solve's
// tolerance times g Δt), and each unknown above the plate, the plate's far part in its cut
// cells included, holds g (H − y) at its cell's centre to 1e-9 of g H. With the plate 0.1,
// 0.32, 0.68 and 0.9 of a cell above a plane of centres: the far part lies above the centre
// (the film on the plate) or below it (the sliver of the water underneath).
TEST(CutCellSystem, StillWaterOnBothSidesOfAPlateStaysStillWithEachSidesPressure) {
  for (const double h : {0.1, 0.32, 0.68, 0.9}) {
    const double plate = (5.5 + h) * kDx, surface = plate + 2.7 * kDx;
    const test::CutShells scene = test::CutShells(
        kGrid, {test::make_plate({0.25, plate, 0.25}, Eigen::Vector3d::UnitY(), 2.0, 9)});
    const CellParts& parts = scene.parts;
    ASSERT_EQ(parts.parts().size(), 2u * 64u) << "h " << h;
    // φ above the plate: the distance to the surface; below it the tank is full (deep).
    const auto phi_at = [&](double y, bool above_plate) {
      return above_plate ? y - surface : -1.0;
    };
    std::vector<double> cell_phi(kGrid.size(Location::Cell)), part_phi(parts.parts().size());
    for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c) {
      const double y = kGrid.position(Location::Cell, c).y();
      cell_phi[c] = phi_at(y, y > plate);
    }
    for (size_t p = 0; p < parts.parts().size(); ++p) {
      const CellPart& part = parts.parts()[p];
      const double y = kGrid.position(Location::Cell, part.cell).y();
      part_phi[p] = phi_at(y, part.corners == 0xCC);  // the part holding the upper corners
    }
    CutCellSystem system;
    system.build(kGrid, parts, DomainBoundary(), {cell_phi, part_phi});
    ASSERT_GT(system.laplacian().extras(), 0);

    MacGrid mac(kGrid);
    FragmentVelocities fragments = parts.still_fragments();
    auto& v = mac.face_velocity(1);
    for (std::int64_t f = 0; f < kGrid.size(Location::FaceY); ++f) {
      const int j = kGrid.coordinates(Location::FaceY, f).y();
      v[f] = j == 0 || j == kGrid.cells().y() ? 0.0 : -kGravity * kDt;  // walls stay shut
    }
    std::fill(fragments[1].begin(), fragments[1].end(), -kGravity * kDt);
    const Eigen::VectorXd p = test::project_on_parts(system, mac, fragments);

    // Still where water is.
    const auto wet = [&](int u) { return u >= 0 && system.liquid(u); };
    for (int a = 0; a < 3; ++a) {
      const Location loc = face_location(a);
      for (std::int64_t f = 0; f < kGrid.size(loc); ++f) {
        if (parts.split(a, f) != nullptr) continue;
        const Eigen::Vector3i ijk = kGrid.coordinates(loc, f);
        Eigen::Vector3i below = ijk;
        below[a] -= 1;
        const bool water = (ijk[a] < kGrid.cells()[a] && wet(kGrid.index(Location::Cell, ijk))) ||
                           (below[a] >= 0 && wet(kGrid.index(Location::Cell, below)));
        if (water) {
          EXPECT_NEAR(mac.face_velocity(a)[f], 0.0, 1e-9) << "h " << h << " axis " << a;
        }
      }
      for (const double fragment : fragments[a]) EXPECT_NEAR(fragment, 0.0, 1e-9) << "h " << h;
    }
    // Each side's pressure, the far parts' at their centres.
    const double to_pressure = kDx / kDt;
    for (size_t q = 0; q < parts.parts().size(); ++q) {
      const CellPart& part = parts.parts()[q];
      if (part.corners != 0xCC) continue;
      const double y = kGrid.position(Location::Cell, part.cell).y();
      EXPECT_NEAR(p[system.unknown_of_part(static_cast<int>(q))] * to_pressure,
                  kGravity * (surface - y), 1e-9 * kGravity * surface)
          << "h " << h << (part.slot ? ", the slot" : ", the far part");
    }
  }
}

// A tank full of water cut by a plate across it and by a plate over its middle (whose edges
// the water passes round): a random flow projected leaves no part any divergence (1e-10 of the
// largest |u*|, the solve's tolerance) and does not gain kinetic energy, Σ β u² over faces and
// fragments (an orthogonal projection in that norm can only lose it).
TEST(CutCellSystem, AProjectedFlowLeavesEveryPartDivergenceFreeAndGainsNoEnergy) {
  const test::CutShells scene = test::CutShells(
      kGrid, {test::make_plate({0.25, 5.82 * kDx, 0.25}, Eigen::Vector3d::UnitY(), 2.0, 9),
              test::make_plate({0.25, 10.3 * kDx, 0.25},
                               Eigen::Vector3d(0.2, 1.0, 0.1).normalized(), 0.25, 7)});
  const CellParts& parts = scene.parts;
  const std::vector<double> cell_phi(kGrid.size(Location::Cell), -1.0);
  const std::vector<double> part_phi(parts.parts().size(), -1.0);
  CutCellSystem system;
  system.build(kGrid, parts, DomainBoundary(), {cell_phi, part_phi});
  MacGrid mac(kGrid);
  FragmentVelocities fragments = parts.still_fragments();
  test::random_flow(mac, fragments, 1.0, 5);
  const auto energy = [&] {
    double e = 0.0;
    for (int a = 0; a < 3; ++a) {
      const Location loc = face_location(a);
      for (std::int64_t f = 0; f < kGrid.size(loc); ++f)
        if (parts.split(a, f) == nullptr) e += mac.face_velocity(a)[f] * mac.face_velocity(a)[f];
      for (const FaceSplit& split : parts.split_faces(a)) {
        const auto list = parts.fragments_of(a, split);
        for (size_t k = 0; k < list.size(); ++k)
          e += list[k].aperture * std::pow(fragments[a][split.first + k], 2);
      }
    }
    return 0.5 * e;
  };
  const double before = energy();
  test::project_on_parts(system, mac, fragments);
  Eigen::VectorXd flux;
  system.outward_flux(mac, fragments, flux);
  EXPECT_LE(flux.lpNorm<Eigen::Infinity>(), 1e-10);
  EXPECT_LT(energy(), before);
}

}  // namespace
}  // namespace shellflow::grid_fluid
