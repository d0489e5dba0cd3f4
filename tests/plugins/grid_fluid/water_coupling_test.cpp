// Two-way water (§5.1 with a free surface, §4.3, §6): the coupling pressure is solved over
// the water's cells only, with air at p = 0, so a hull that keeps air out feels the weight
// of the water it displaces (Archimedes, no hand-written buoyancy), a shell in air feels
// nothing and a sheet under water feels no net push. The shells are an open box (walls and
// a bottom, geometry::make_open_box) held still or free to heave, in a 1 m tank at 32³.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

#include "grid_fluid_test_support.hpp"
#include "shellflow/coupling/coupling_loop.hpp"

namespace shellflow::grid_fluid {
namespace {

constexpr double kForever = 1e9;  // no frame end inside these runs
constexpr double kRho = 1000.0;   // the water's default density [kg/m³]
constexpr double kG = 9.81;
constexpr int kResolution = 32;
constexpr double kDx = 1.0 / kResolution;
constexpr double kPool = 0.5;  // water level [m]
constexpr double kSide = 0.4;  // the box's width and depth [m]
constexpr double kWall = 0.3;  // its height [m]
// Off the grid's planes so that no wall lies on a face or a node: the walls cut faces.
const Eigen::Vector3d kAxis(0.513, 0.0, 0.487);

/// An open box (no +y face) whose bottom is at height `bottom`, centred on kAxis.
sdk::ShellSurface make_box(double bottom, double sigma) {
  const auto mesh = geometry::make_open_box({kSide, kWall, kSide}, 12);
  sdk::ShellSurface s;
  s.name = "box";
  s.positions = mesh.positions;
  const Eigen::Vector3d offset(kAxis.x(), bottom + 0.5 * kWall, kAxis.z());
  s.positions.rowwise() += offset.transpose();
  s.velocities = sdk::Positions::Zero(s.positions.rows(), 3);
  s.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  s.surface_density = Eigen::VectorXd::Constant(mesh.triangles.rows(), sigma);
  return s;
}

/// A still pool up to kPool; with `dry_box_bottom` the inside of the box standing there
/// (above its bottom) is air, else the water fills it.
nlohmann::json tank(std::optional<double> dry_box_bottom, int resolution = kResolution) {
  nlohmann::json initial = nlohmann::json::array({{{"type", "pool"}, {"height", kPool}}});
  if (dry_box_bottom) {
    const double h = 0.5 * kSide;
    initial.push_back({{"type", "box"},
                       {"min", {kAxis.x() - h, *dry_box_bottom, kAxis.z() - h}},
                       {"max", {kAxis.x() + h, 1.0, kAxis.z() + h}},
                       {"subtract", true}});
  }
  return {{"domain", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}}},
          {"resolution", resolution},
          {"pressure", {{"tolerance", 1e-9}, {"coupling_tolerance", 1e-9}}},
          {"water", {{"initial", initial}}}};
}

/// The mean of the held box's force over steps 2..`steps` of a still tank (step 1 starts
/// the loop's look-ahead from rest).
Eigen::Vector3d held_force(double bottom, std::optional<double> dry_bottom, int steps = 8) {
  auto fluid = test::make_fluid(tank(dry_bottom));
  // σ so large (β = ρΔx/σ ≈ 1e-6) that the box is a wall to the solve: the force of
  // still water on a body that does not move.
  test::TranslatingShell box(make_box(bottom, 3e7), 1, -kG, /*held=*/true);
  coupling::CouplingLoop loop(fluid.get(), {&box}, {0.5, 0.01});
  loop.start(0.0, kForever);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int step = 1; step <= steps; ++step) {
    loop.step(loop.next_dt(kForever), kForever);
    if (step >= 2) sum += box.force();
  }
  return sum / (steps - 1);
}

class HeldBoxDraft : public ::testing::TestWithParam<double> {};

TEST_P(HeldBoxDraft, FeelsTheWeightOfTheWaterItKeepsOut) {
  const double draft = GetParam();
  const double bottom = kPool - draft;
  const Eigen::Vector3d f = held_force(bottom, bottom);
  const double archimedes = kRho * kG * kSide * kSide * draft;
  std::printf("held box, draft %.3f m: F = (%.3f, %.3f, %.3f) N, ρ g V = %.3f N\n", draft, f.x(),
              f.y(), f.z(), archimedes);
  // The jump is taken at the bottom (each side extrapolated there) and the surface sits at
  // its ghost-fluid location, so the hydrostatic force is exact up to the spread of the
  // jumps to the triangles (step 3–4), which smears it over ~Δx at the rim: the bottom's
  // edge strip of width Δx/2 is 2.5 % of the lift here (4 · Δx/2 / a); 3 % bound.
  EXPECT_NEAR(f.y(), archimedes, 0.03 * archimedes);
  // The box is symmetric and the tank still: sideways forces cancel to the walls' spread
  // error (1 % of the lift).
  EXPECT_LE(std::hypot(f.x(), f.z()), 0.01 * archimedes);
}

// The bottom 0.2 Δx and 0.53 Δx above the cell centres below it (the raw jump between
// the centres would be 14 % too large at the first).
INSTANTIATE_TEST_SUITE_P(WaterCoupling, HeldBoxDraft, ::testing::Values(0.15, 0.171));

TEST(WaterCoupling, HeldBoxInTheAirFeelsNoPressure) {
  // The whole box above the surface: every face it cuts has air on both sides.
  const Eigen::Vector3d f = held_force(kPool + 3.0 * kDx, std::nullopt);
  EXPECT_EQ(f.norm(), 0.0) << "F = " << f.transpose();
}

TEST(WaterCoupling, NoSolveWhileNoWaterTouchesATwoWayShell) {
  // Cost follows what the scene uses: with air on both sides of every face the box cuts,
  // every jump is zero, so the coupling solve is skipped (no iterations); once the box is
  // lowered into the water it is solved again.
  const auto iterations = [](double bottom) {
    auto fluid = test::make_fluid(tank(std::nullopt));
    test::TranslatingShell box(make_box(bottom, 3e7), 1, -kG, /*held=*/true);
    coupling::CouplingLoop loop(fluid.get(), {&box}, {0.5, 0.01});
    loop.start(0.0, kForever);
    loop.step(loop.next_dt(kForever), kForever);
    return test::reported(*fluid, "coupling_iterations");
  };
  EXPECT_EQ(iterations(kPool + 3.0 * kDx), 0.0);
  EXPECT_GT(iterations(kPool - 0.1), 0.0);
}

TEST(WaterCoupling, FloodedBoxFeelsNoNetPressure) {
  // Submerged and full of water: the bottom has water at the same hydrostatic pressure on
  // both sides. Taking the jump between the cell centres instead would lift the bottom by
  // ρ g Δx a² (the buoyancy of a Δx-thick slab); a tenth of that is the bound.
  const double bottom = 0.1;  // the rim at 0.4, under the surface at 0.5
  const Eigen::Vector3d f = held_force(bottom, std::nullopt);
  const double slab = kRho * kG * kDx * kSide * kSide;
  std::printf("flooded box: F = (%.3f, %.3f, %.3f) N, slab ρ g Δx a² = %.3f N\n", f.x(), f.y(),
              f.z(), slab);
  EXPECT_LE(f.norm(), 0.1 * slab);
}

class HeldHeeledBox : public ::testing::TestWithParam<double> {};

TEST_P(HeldHeeledBox, FeelsTheMomentOfTheWaterItKeepsOut) {
  // The box heeled about z, its inside dry: still water pushes on it with the buoyancy
  // ρ g V at the centroid of the volume V it keeps out (the hull's inside below the level),
  // so about the box's centre the moment is (x_B − x_P) ρ g V. The solve's faces stand for
  // the pieces of shell they sample, whole normals and all (rigid_face_areas.hpp): with a
  // whole face per cut along its axis alone, the moment at 3 degrees came out +0.97 N m
  // (the water's push on the walls, whose vertical part no face took, is a couple), and a
  // free box rolled over to 7 degrees.
  const double heel_deg = GetParam();
  const double heel = heel_deg * std::acos(-1.0) / 180.0;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(heel, Eigen::Vector3d::UnitZ()).matrix();
  const Eigen::Vector3d centre(kAxis.x(), 0.35 + 0.5 * kWall, kAxis.z());
  auto box_surface = make_box(0.35, 3e7);
  for (int i = 0; i < box_surface.node_count(); ++i)
    box_surface.positions.row(i) =
        (centre + rotation * (box_surface.positions.row(i).transpose() - centre)).transpose();
  // The hull's inside dry: a closed box from its bottom to above the water, heeled alike.
  const Eigen::Vector3d inside_centre = centre + rotation * Eigen::Vector3d(0.0, 0.5 * kWall, 0.0);
  auto config = tank(std::nullopt);
  config["water"]["initial"].push_back(
      {{"type", "mesh"},
       {"mesh", {{"type", "box"}, {"size", {kSide, 2.0 * kWall, kSide}}, {"divisions", 4}}},
       {"transform",
        {{"rotate_axis", {0, 0, 1}},
         {"rotate_deg", heel_deg},
         {"translate", {inside_centre.x(), inside_centre.y(), inside_centre.z()}}}},
       {"subtract", true}});
  auto fluid = test::make_fluid(config);
  test::TranslatingShell box(box_surface, 1, -kG, /*held=*/true);
  coupling::CouplingLoop loop(fluid.get(), {&box}, {0.5, 0.01});
  loop.start(0.0, kForever);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  const int steps = 8;
  for (int step = 1; step <= steps; ++step) {
    loop.step(loop.next_dt(kForever), kForever);
    if (step < 2) continue;
    force += box.force() / (steps - 1);
    moment += box.moment_about(centre) / (steps - 1);
  }
  // The kept-out volume and its centroid, by the midpoint rule on a 200³ lattice of the
  // box's inside (its own frame): 1e-4 of the moment's size.
  const int n = 200;
  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  const double cell = (kSide / n) * (kWall / n) * (kSide / n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d local((i + 0.5) / n * kSide - 0.5 * kSide,
                                    (j + 0.5) / n * kWall - 0.5 * kWall,
                                    (k + 0.5) / n * kSide - 0.5 * kSide);
        const Eigen::Vector3d p = centre + rotation * local;
        if (p.y() >= kPool) continue;
        volume += cell;
        first += cell * p;
      }
  const double lift = kRho * kG * volume;
  const double expected = (first.x() / volume - centre.x()) * lift;  // τ_z = r_x F_y
  std::printf(
      "held box heeled %.0f degrees: F = (%.3f, %.3f, %.3f) N (ρ g V = %.3f N), moment "
      "about its centre (%.3f, %.3f, %.3f) N m, expected τ_z = %.3f N m\n",
      heel_deg, force.x(), force.y(), force.z(), lift, moment.x(), moment.y(), moment.z(),
      expected);
  EXPECT_NEAR(force.y(), lift, 0.03 * lift);  // the upright box's bound (above)
  // The surface cuts each wall within a cell, where a face reads the jump of the cell
  // centre's depth: up to ρ g Δx/2 over a Δx-high strip of a wall of width a, at a lever
  // of up to H/2 (H the wall's height): 0.29 N m here, against 0.62 N m at 10 degrees.
  const double waterline = kRho * kG * 0.5 * kDx * kDx * kSide * 0.5 * kWall;
  EXPECT_NEAR(moment.z(), expected, waterline);
  EXPECT_NEAR(moment.x(), 0.0, waterline);  // no heel about x: no moment about it
}

INSTANTIATE_TEST_SUITE_P(WaterCoupling, HeldHeeledBox, ::testing::Values(0.0, 4.0, 10.0, -10.0));

TEST(WaterCouplingSlow, FreeBoxFloatsAtTheDraftItsMassImplies) {
  // Archimedes with nothing but the §5.1 pressure, the box one rigid body in the solve
  // (sdk::RigidBody): an open box of mass M floats where the water it keeps out weighs M,
  // draft d = M/(ρ a²) below the water level around it. Released a cell higher, it heaves
  // about that draft, the waves it makes carrying the motion away. At 48³, the issue's
  // resolution. The draft is measured from the level in the tank's corners, which rises as
  // the box sinks in (by a²/(1 − a²) of what it sinks: 0.19 Δx for the first cell).
  const int resolution = 48;
  const double dx = 1.0 / resolution;
  const double draft = 0.15;
  const double area = kSide * kSide + 4.0 * kSide * kWall;
  const double sigma = kRho * kSide * kSide * draft / area;  // 37.5 kg/m²
  const double bottom = kPool - draft + dx;
  auto fluid = test::make_fluid(tank(bottom, resolution));
  test::TranslatingShell box(make_box(bottom, sigma), 1, -kG, /*held=*/false);
  coupling::CouplingLoop loop(fluid.get(), {&box}, {0.5, 0.01});
  loop.start(0.0, kForever);
  // The heave decays by about half every 0.5 s (its period): measured over the last 0.5 s.
  const double end = 4.0;
  double sum = 0.0,
         time = 0.0;  // ∫ (d − draft) dt over the last half second, d the Archimedes draft
  double last_speed = 0.0;  // max |v| over the same
  double next_print = 0.0, speed = 0.0;
  while (loop.time() < end) {
    const double dt = loop.next_dt(kForever);
    loop.step(dt, kForever);
    double level = 0.0;
    for (const double x : {0.1, 0.9})
      for (const double z : {0.1, 0.9}) level += 0.25 * test::surface_height(*fluid, x, z);
    const double offset = draft - (level - (bottom + box.offset()));  // > 0: floats high
    speed = std::max(speed, std::abs(box.velocity()));
    if (loop.time() >= next_print) {
      std::printf("t = %.2f s: level %.5f m, d − draft %+.5f m (%+.3f dx), max |v| %.5f m/s\n",
                  loop.time(), level, offset, offset / dx, speed);
      speed = 0.0;
      next_print += 0.25;
    }
    if (loop.time() > end - 0.5) {
      sum += offset * dt;
      time += dt;
      last_speed = std::max(last_speed, std::abs(box.velocity()));
    }
  }
  std::printf(
      "over the last 0.5 s: mean d − draft %+.5f m = %+.3f dx (> 0: floats high, d Archimedes), "
      "max |v| %.2e m/s = %.3f sqrt(g dx)\n",
      sum / time, sum / time / dx, last_speed, last_speed / std::sqrt(kG * dx));
  // The bounds: the draft within Δx/4, at rest to 1 % of √(gΔx).
  EXPECT_NEAR(sum / time, 0.0, 0.25 * dx) << "mean offset from the Archimedes draft";
  EXPECT_LE(last_speed, 0.01 * std::sqrt(kG * dx));
}

TEST(WaterCouplingSlow, FreeBoxIsStableOverTheDensitySweep) {
  // The smoke coupling's sweep in water: the open box free to heave, σ from 10⁻³ to 10³ times
  // ρΔx (the water's mass per unit area of one cell layer, 31.25 kg/m² here), at CFL 0.5 and
  // 2 with the step up to 0.02 s, over 0.25 s, released a cell above the draft of 37.5 kg/m²: the
  // light ones pop up and float, the heavy ones fall. Bound: finite, and no faster than a free fall
  // from rest over the run plus √(gΔx) (a body the water does not hold up).
  const double bottom = kPool - 0.15 + kDx;
  const double rho_dx = kRho * kDx;
  for (const double cfl : {0.5, 2.0}) {
    std::printf("CFL %.1f, max |v| [m/s] for σ/ρΔx = 1e-3 .. 1e3:", cfl);
    for (int e = -3; e <= 3; ++e) {
      const double sigma = rho_dx * std::pow(10.0, e);
      auto fluid = test::make_fluid(tank(bottom));
      test::TranslatingShell box(make_box(bottom, sigma), 1, -kG, /*held=*/false);
      coupling::CouplingLoop loop(fluid.get(), {&box}, {cfl, 0.02});
      loop.start(0.0, kForever);
      double fastest = 0.0;
      while (loop.time() < 0.25) {
        loop.step(loop.next_dt(kForever), kForever);
        ASSERT_TRUE(std::isfinite(box.velocity())) << "σ = " << sigma << ", CFL " << cfl;
        fastest = std::max(fastest, std::abs(box.velocity()));
      }
      std::printf(" %.3f", fastest);
      EXPECT_LE(fastest, kG * 0.25 + std::sqrt(kG * kDx)) << "σ = " << sigma << ", CFL " << cfl;
    }
    std::printf("\n");
  }
}

TEST(WaterCoupling, ALightPlateYieldsToAStreamThatAHeavyOneStops) {
  // One stream on two plates free to move along y (no gravity of their own), one 1000×
  // the other's mass. The force is the §5.1 jump, and a plate that yields lowers it: the
  // light one moves more, but the stream pushes it with less force than it pushes the
  // heavy one, which stops it (a force set by the stream alone would push both alike).
  // Mean force over the run [N] and the plate's travel [m]: 0.45 s, the stream landing at
  // about 0.15 s (0.25 m of fall from the source's foot at 1 m/s).
  const auto push = [](double sigma) {
    auto fluid = test::make_fluid({{"domain", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}}},
                                   {"resolution", kResolution},
                                   {"water",
                                    {{"sources",
                                      {{{"shape", "cylinder"},
                                        {"from", {0.5, 0.85, 0.5}},
                                        {"to", {0.5, 1.0, 0.5}},
                                        {"radius", 0.08},
                                        {"velocity", {0, -1, 0}}}}}}}});
    auto surface =
        test::make_plate(Eigen::Vector3d(0.513, 0.6, 0.487), Eigen::Vector3d::UnitY(), 0.4, 17);
    surface.surface_density.setConstant(sigma);
    test::TranslatingShell plate(surface, 1, 0.0, /*held=*/false);
    coupling::CouplingLoop loop(fluid.get(), {&plate}, {0.5, 0.01});
    loop.start(0.0, kForever);
    double impulse = 0.0;
    while (loop.time() < 0.45) {
      const double dt = loop.next_dt(kForever);
      loop.step(dt, kForever);
      impulse += plate.force().y() * dt;
    }
    return std::pair{impulse / loop.time(), plate.offset()};
  };
  const double rho_dx = kRho * kDx;
  const auto [light_force, light_travel] = push(0.1 * rho_dx);
  const auto [heavy_force, heavy_travel] = push(100.0 * rho_dx);
  std::printf(
      "stream on a plate of σ = 0.1 ρΔx: mean force %.3f N, travel %.4f m; of 100 ρΔx: "
      "%.3f N, %.6f m\n",
      light_force, light_travel, heavy_force, heavy_travel);
  // Both pushed down; the light one further, with less force.
  EXPECT_LT(heavy_force, 0.0);
  EXPECT_LT(light_travel, heavy_travel);
  EXPECT_LT(std::abs(light_force), std::abs(heavy_force));
}

}  // namespace
}  // namespace shellflow::grid_fluid
