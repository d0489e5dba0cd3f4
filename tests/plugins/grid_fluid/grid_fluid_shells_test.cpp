// Thin shells in the smoke (§3, §4.1–4.3): still air stays still, sealed plates and
// deforming sheets leak nothing, a sweeping plate carries no tracer across, an enclosed
// pocket solves every step; the divergence after every projection stays below tolerance.
// Water in a cup shaken sideways keeps its volume (§4.4.1 next to a moving shell).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "grid_fluid_test_support.hpp"
#include "shellflow/coupling/coupling_loop.hpp"
#include "shellflow/kinematic_shell/kinematic_shell.hpp"
#include "shellflow/runtime/scene.hpp"
#include "shellflow/sdk/json_helpers.hpp"
#include "test_paths.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

/// Smoke on each side of a plane (point c, normal n): {behind (n·(x−c) < −ε), ahead (> ε)}.
std::array<double, 2> smoke_by_side(const GridFluid& fluid, const Eigen::Vector3d& c,
                                    const Eigen::Vector3d& n) {
  std::array<double, 2> sums{0.0, 0.0};
  const auto& g = fluid.grid();
  const auto& rho = fluid.nodes().density();
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(rho.size()); ++i) {
    const double d = n.dot(g.position(Location::Node, i) - c);
    if (d < -fluid.epsilon()) sums[0] += rho[i];
    if (d > fluid.epsilon()) sums[1] += rho[i];
  }
  return sums;
}

/// Plane of a flat shell: its centroid and the unit normal of its first triangle.
std::pair<Eigen::Vector3d, Eigen::Vector3d> plane_of(const sdk::ShellSurface& s) {
  const geometry::TriangleMesh mesh(s);
  return {s.positions.colwise().mean().transpose(), mesh.scaled_normal(0).normalized()};
}

struct SceneRun {
  runtime::Scene scene;
  std::unique_ptr<GridFluid> fluid;
  std::unique_ptr<kinematic_shell::KinematicShell> solid;
  std::unique_ptr<coupling::CouplingLoop> loop;
};

/// Loads a configs/verify scene (validated against the built plugins' schemas) and builds
/// its fluid (its parameters passed through `edit`, when given) and single kinematic solid
/// from the core libraries.
SceneRun load(const std::string& name, const std::function<void(nlohmann::json&)>& edit = nullptr) {
  SceneRun run;
  run.scene = runtime::load_scene(shellflow::test_paths::source_dir() + "/configs/verify/" + name,
                                  {shellflow::test_paths::plugin_dir()});
  if (edit) edit(run.scene.fluid->params);
  sdk::Context context;
  context.gravity = run.scene.gravity;
  context.fps = run.scene.time.fps;
  context.instance_name = run.scene.fluid->instance_name;
  run.fluid = std::make_unique<GridFluid>(run.scene.fluid->params, context);
  context.instance_name = run.scene.solids.at(0).instance_name;
  run.solid = std::make_unique<kinematic_shell::KinematicShell>(run.scene.solids[0].params, context);
  run.loop = std::make_unique<coupling::CouplingLoop>(
      run.fluid.get(), std::vector<sdk::SolidSolver*>{run.solid.get()},
      coupling::StepLimits{run.scene.time.cfl, run.scene.time.max_dt});
  return run;
}

/// Starts a water scene's loop at its frame step and takes its first step, which measures the
/// water it starts with: returns that volume [m^3].
double start_water_scene(SceneRun& run) {
  const double dt0 = 1.0 / run.scene.time.fps;
  run.loop->start(0.0, dt0);
  run.loop->step(run.loop->next_dt(dt0), dt0);
  return test::reported(*run.fluid, "water_volume") -
         test::reported(*run.fluid, "water_volume_change");
}

TEST(GridFluidShells, StillAirAroundAStaticTiltedShellStaysStill) {
  auto fluid = test::make_fluid({{"resolution", 16}, {"smoke", {{"vorticity_confinement", 0.3}}}});
  const auto plate =
      test::make_plate({0.5, 0.45, 0.52}, Eigen::Vector3d(0.3, 1.0, -0.5).normalized(), 0.5, 6);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v_eff{plate.velocities};
  double t = 0.0;
  for (int step = 0; step < 100; ++step) {
    fluid->advect(t, 0.02, shells, shells);
    fluid->project(0.02, shells, v_eff);
    t += 0.02;
  }
  EXPECT_GT(fluid->last_step().projection.shell_neumann_faces, 0);
  // Exactly zero is the answer; 1e-10 is the bound (round-off could only ever
  // produce ~1e-16 here).
  EXPECT_LE(fluid->mac().max_face_speed(), 1e-10);
}

TEST(GridFluidShells, SealedPlateTranslatingAndRotatingLeaksNothing) {
  auto run = load("smoke_sealed_plate.json");
  const double tol = run.scene.fluid->params.at("pressure").at("tolerance").get<double>();
  const double dt = 0.01;
  run.loop->start(0.0, dt);
  double worst_leak = 0.0;
  double worst_div = 0.0;
  for (int step = 0; step < 200; ++step) {
    run.loop->step(dt, 1.0);
    const auto [c, n] = plane_of(run.loop->shells()[0]);
    const auto sides = smoke_by_side(*run.fluid, c, n);
    const double total = sides[0] + sides[1];
    ASSERT_GT(total, 0.0);
    // The source box lies on the −x side: n points to +x after the transform (90° about y
    // turns +z into +x), so "ahead" (sides[1]) is the other side.
    ASSERT_GT(n.x(), 0.5);
    worst_leak = std::max(worst_leak, sides[1] / total);
    const auto& p = run.fluid->last_step().projection;
    ASSERT_TRUE(p.converged) << "step " << step;
    // Both sides sealed (more when a cell centre lies inside the wedge: its own region).
    EXPECT_GE(p.enclosed_regions, 2) << "step " << step;
    worst_div = std::max(worst_div, p.max_relative_divergence);
    ASSERT_FALSE(run.fluid->find_nonfinite().has_value());
  }
  std::printf("sealed plate: worst leak %.3e, worst relative divergence %.3e\n", worst_leak,
              worst_div);
  EXPECT_LE(worst_leak, 1e-9);  // the bound
  EXPECT_LE(worst_div, tol);    // §4.3 after every projection
  // The plate really turned: its normal is 30° from +x at t = 2 s.
  const auto [c, n] = plane_of(run.loop->shells()[0]);
  EXPECT_NEAR(std::acos(std::clamp(n.x(), -1.0, 1.0)) * 180.0 / std::numbers::pi, 30.0, 1e-6);
}

TEST(GridFluidShellsSlow, SealedWavyDeformingSheetLeaksNothing) {
  auto run = load("smoke_sealed_wavy_sheet.json");
  const double tol = run.scene.fluid->params.at("pressure").at("tolerance").get<double>();
  // The sheet's rest plane is x = 0.5 (normal +x after the transform); the wave moves its
  // nodes along x by A sin(k·x0 − ωt + φ), so the far side at time t is x > 0.5 + that.
  const auto& wave = run.scene.solids.at(0).params.at("motion");
  ASSERT_EQ(wave.at("type"), "wave");
  const double A = wave.at("amplitude").get<double>();
  const Eigen::Vector3d k = sdk::json_vec3(wave, "wave_vector");
  const double omega = wave.at("angular_frequency").get<double>();
  const double phi = wave.at("phase").get<double>();
  const double dt = 0.01;
  run.loop->start(0.0, dt);
  double worst_leak = 0.0;
  double worst_div = 0.0;
  const auto& g = run.fluid->grid();
  for (int step = 0; step < 200; ++step) {
    run.loop->step(dt, 1.0);
    const double t = (step + 1) * dt;
    const auto& rho = run.fluid->nodes().density();
    double other = 0.0, total = 0.0;
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(rho.size()); ++i) {
      const Eigen::Vector3d p = g.position(Location::Node, i);
      const Eigen::Vector3d x0(0.5, p.y(), p.z());
      const double surface = 0.5 + A * std::sin(k.dot(x0) - omega * t + phi);
      total += rho[i];
      // The mesh (node spacing h = 0.05 m) deviates from the analytic sheet by up to
      // A |k|^2 h^2 / 8 ≈ 1.2e-3 m: nodes closer than 3e-3 m are not judged.
      if (p.x() > surface + 3e-3) other += rho[i];
    }
    ASSERT_GT(total, 0.0);
    worst_leak = std::max(worst_leak, other / total);
    const auto& proj = run.fluid->last_step().projection;
    ASSERT_TRUE(proj.converged) << "step " << step;
    EXPECT_GE(proj.enclosed_regions, 2) << "step " << step;  // both sides sealed
    worst_div = std::max(worst_div, proj.max_relative_divergence);
    ASSERT_FALSE(run.fluid->find_nonfinite().has_value());
  }
  std::printf("sealed wavy sheet: worst leak %.3e, worst relative divergence %.3e\n", worst_leak,
              worst_div);
  EXPECT_LE(worst_leak, 1e-9);  // the bound
  EXPECT_LE(worst_div, tol);    // §4.3 after every projection
  // The sheet really deformed: a node's x follows the wave at t = 2 s.
  const auto& shell = run.loop->shells()[0];
  const Eigen::Vector3d rest = run.solid->rest_positions().row(0).transpose();
  EXPECT_NEAR(shell.positions(0, 0), 0.5 + A * std::sin(k.dot(rest) - omega * 2.0 + phi), 1e-9);
}

TEST(GridFluidShells, PlateSweepingThroughStillAirCarriesNoTracerBehindIt) {
  auto run = load("smoke_plate_sweep.json");
  const double dt = 0.01;
  run.loop->start(0.0, dt);
  run.loop->step(dt, 1.0);
  const double initial = run.fluid->smoke_mass();
  ASSERT_GT(initial, 0.0);
  double worst = 0.0;
  for (int step = 1; step < 200; ++step) {
    run.loop->step(dt, 1.0);
    const auto [c, n] = plane_of(run.loop->shells()[0]);
    const auto sides = smoke_by_side(*run.fluid, c, n);
    worst = std::max(worst, sides[0] / (initial / std::pow(run.fluid->grid().dx(), 3)));
    ASSERT_TRUE(run.fluid->last_step().projection.converged);
  }
  std::printf("plate sweep: worst tracer behind the plate %.3e of the initial total\n", worst);
  EXPECT_LE(worst, 1e-9);
  // The plate moved from x = 0.2 to 0.8 (0.3 m/s for 2 s).
  EXPECT_NEAR(plane_of(run.loop->shells()[0]).first.x(), 0.8, 1e-9);
}

/// A wavy sheet spanning the box, deforming in time: x = 0.5 + A sin(2π y − ω t) cos(π z).
sdk::ShellSurface wavy_sheet(double t, const sdk::ShellSurface& rest) {
  constexpr double A = 0.08, w = 3.0;
  sdk::ShellSurface s = rest;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    const double y = rest.positions(i, 1), z = rest.positions(i, 2);
    const double phase = 2 * std::numbers::pi * y - w * t;
    s.positions(i, 0) = 0.5 + A * std::sin(phase) * std::cos(std::numbers::pi * z);
    s.velocities.row(i) = Eigen::RowVector3d(-A * w * std::cos(phase) * std::cos(std::numbers::pi * z), 0, 0);
  }
  return s;
}

TEST(GridFluidShells, WavyDeformingSheetLeaksNothing) {
  auto fluid = test::make_fluid(
      {{"resolution", 16},
       {"pressure", {{"tolerance", 1e-8}}},
       {"sources", nlohmann::json::array({{{"shape", "box"},
                                           {"min", {0.02, 0.2, 0.2}},
                                           {"max", {0.25, 0.8, 0.8}},
                                           {"velocity", {0.6, 0.0, 0.0}},
                                           {"end", 1.0}}})}});
  // The flat rest sheet x = 0.5 spans y, z in [-0.5, 1.5] (beyond the box: a seal).
  const auto rest = test::make_plate({0.5, 0.5, 0.5}, Eigen::Vector3d::UnitX(), 2.0, 41);
  const double dt = 0.01;
  double worst = 0.0;
  auto at = [&](int n) { return std::vector<sdk::ShellSurface>{wavy_sheet(n * dt, rest)}; };
  for (int step = 0; step < 200; ++step) {
    const auto s_n = at(step), s_np1 = at(step + 1), s_np2 = at(step + 2);
    fluid->advect(step * dt, dt, s_n, s_np1);
    const std::vector<sdk::Positions> v_eff{(s_np2[0].positions - s_np1[0].positions) / dt};
    fluid->project(dt, s_np1, v_eff);
    // Side test against the analytic surface: behind = x below the sheet at (y, z).
    const auto& g = fluid->grid();
    const auto& rho = fluid->nodes().density();
    double other = 0.0, total = 0.0;
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(rho.size()); ++i) {
      const Eigen::Vector3d p = g.position(Location::Node, i);
      const double surface = 0.5 + 0.08 * std::sin(2 * std::numbers::pi * p.y() - 3.0 * (step + 1) * dt) *
                                       std::cos(std::numbers::pi * p.z());
      total += rho[i];
      // The mesh (node spacing h = 0.05) deviates from the analytic sheet by up to
      // A (2π)² h² / 8 ≈ 2e-3 along a diagonal: nodes closer than that are not judged.
      if (p.x() > surface + 3e-3) other += rho[i];
    }
    ASSERT_GT(total, 0.0);
    worst = std::max(worst, other / total);
    ASSERT_TRUE(fluid->last_step().projection.converged);
  }
  std::printf("wavy sheet: worst smoke on the far side %.3e\n", worst);
  EXPECT_LE(worst, 1e-9);
}

TEST(GridFluidShells, EnclosedMovingPocketSolvesEveryStep) {
  auto fluid = test::make_fluid(
      {{"resolution", 16},
       {"pressure", {{"tolerance", 1e-8}}},
       {"sources", nlohmann::json::array({{{"shape", "sphere"},
                                           {"center", {0.4, 0.5, 0.5}},
                                           {"radius", 0.08},
                                           {"end", 0.02}}})}});
  auto box = geometry::make_box(Eigen::Vector3d(0.36, 0.36, 0.36), 3);
  sdk::ShellSurface rest;
  rest.positions = box.positions;
  rest.triangles = std::make_shared<const sdk::Triangles>(box.triangles);
  rest.velocities = sdk::Positions::Zero(rest.positions.rows(), 3);
  // Translating along +x at 0.2 m/s and spinning about z at 1 rad/s, centred at (0.4 + 0.2t, 0.5, 0.5).
  auto at = [&](double t) {
    sdk::ShellSurface s = rest;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d c(0.4 + 0.2 * t, 0.5, 0.5);
    for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
      const Eigen::Vector3d arm = R * rest.positions.row(i).transpose();
      s.positions.row(i) = (c + arm).transpose();
      s.velocities.row(i) = (Eigen::Vector3d(0.2, 0, 0) + Eigen::Vector3d::UnitZ().cross(arm)).transpose();
    }
    return std::vector<sdk::ShellSurface>{s};
  };
  const double dt = 0.02;
  for (int step = 0; step < 50; ++step) {
    const auto s_n = at(step * dt), s_np1 = at((step + 1) * dt), s_np2 = at((step + 2) * dt);
    fluid->advect(step * dt, dt, s_n, s_np1);
    const std::vector<sdk::Positions> v_eff{(s_np2[0].positions - s_np1[0].positions) / dt};
    fluid->project(dt, s_np1, v_eff);
    const auto& p = fluid->last_step().projection;
    ASSERT_TRUE(p.converged) << "step " << step;
    ASSERT_GE(p.enclosed_regions, 2) << "step " << step;  // the pocket and the walled outside
    ASSERT_LE(p.max_relative_divergence, 1e-8) << "step " << step;
    ASSERT_FALSE(fluid->find_nonfinite().has_value()) << *fluid->find_nonfinite();
  }
  // The smoke released inside the pocket is still all inside it (rigid motion: the box
  // interior is |R^T (x − c)|_inf < 0.18).
  const Eigen::Matrix3d R = Eigen::AngleAxisd(50 * dt, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d c(0.4 + 0.2 * 50 * dt, 0.5, 0.5);
  const auto& g = fluid->grid();
  const auto& rho = fluid->nodes().density();
  double inside = 0.0, outside = 0.0;
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(rho.size()); ++i) {
    const Eigen::Vector3d local = R.transpose() * (g.position(Location::Node, i) - c);
    (local.cwiseAbs().maxCoeff() < 0.18 ? inside : outside) += rho[i];
  }
  EXPECT_GT(inside, 0.0);
  EXPECT_LE(outside, 1e-9 * inside);
}

TEST(GridFluidShellsSlow, WaterInAShakenCupMakesNoWater) {
  // configs/verify/water_sloshing_cup at 32 cells across (the cup 4 cells in radius), the
  // level set alone, 5 s: the cup moves ±0.02 m (0.64Δx) sideways once a second and the
  // water sloshes below its rim. Air nodes next to the wall whose extrapolated velocity
  // moved them off it carried the wall's wet side out into the air, and the water rose up
  // the wall: +32 % by 5 s here (+55 % in 7.5 s at 48 cells with 16 particles per cell).
  // The volume swings with the wall's motion: −2.0 … +5.2 % here now (ends +3.1 %). The
  // nodes a wall sweeps took the average of their neighbours, which lost water (−15 % of it
  // in 5 s, by phase), behind a gain in reinitialisation next to the walls (+11.5 %): −8.0
  // … +0.1 % (ends −2.0 %). They now take φ where the water there came from, and the gain
  // showed (−1.8 … +5.5 %, ends +3.9 %): most of it was the Euler ray's own, which grows
  // the traced water in irrotational flow. Traced from the midpoint (6 Dec 2026): −3.8 …
  // +1.8 %, ends −2.1 % (README, Known limits); read with the cells at the bottom's rim
  // sampled, −3.6 … +0.7 %, ends −3.0 %; with the pressure solves' face fractions (a cell
  // the wall cuts passes the flow of its centre's side only), −2.5 … +0.9 %, ends −2.1 %.
  // The bounds: the widest of these swings and half again.
  auto run = load("water_sloshing_cup.json", [](nlohmann::json& fluid) {
    fluid["resolution"] = 32;
    fluid["water"]["particles"]["per_cell"] = 0;
  });
  const double dt0 = 1.0 / run.scene.time.fps;
  const double v0 = start_water_scene(run);
  const auto volume = [&] { return test::reported(*run.fluid, "water_volume"); };
  double lowest = v0, highest = v0;
  while (run.loop->time() < 5.0 - 1e-9) {
    run.loop->step(run.loop->next_dt(dt0), dt0);
    lowest = std::min(lowest, volume());
    highest = std::max(highest, volume());
    ASSERT_FALSE(run.fluid->find_nonfinite().has_value());
  }
  std::printf(
      "[  figure  ] shaken cup, 32 cells, level set alone, 5 s: water %+.1f %% "
      "(%+.1f … %+.1f %%)\n",
      100.0 * (volume() / v0 - 1.0), 100.0 * (lowest / v0 - 1.0), 100.0 * (highest / v0 - 1.0));
  EXPECT_LT(highest, 1.03 * v0);
  EXPECT_GT(lowest, 0.94 * v0);
}

/// A verify scene with /fluid/water/cut_cells on (and no particles: not on cut cells yet).
SceneRun load_on_cut_cells(const std::string& name) {
  return load(name, [](nlohmann::json& fluid) {
    fluid["water"]["cut_cells"] = true;
    fluid["water"]["particles"]["per_cell"] = 0;
  });
}

// Cut cells (issue #52): configs/verify/water_sheet_on_tilted_plate (48 cells, a sheet two
// cells thick sliding down a plate tilted 20 degrees across a closed tank) with
// /fluid/water/cut_cells on (no particles: not on cut cells yet). The bounds are #52's "done
// means", not measurements (those: docs/measured-figures.md): the water's drift over the second
// within a hundredth of it, and no water faster than 3 √(2 g H), H = 1 m the tank's height.
TEST(GridFluidShellsSlow, ASheetOnATiltedPlateOnCutCellsKeepsItsWater) {
  auto run = load_on_cut_cells("water_sheet_on_tilted_plate.json");
  const double dt0 = 1.0 / run.scene.time.fps;
  const double v0 = start_water_scene(run);
  const auto volume = [&] { return test::reported(*run.fluid, "water_volume"); };
  double fastest = 0.0, worst = 0.0;
  while (run.loop->time() < 1.0 - 1e-9) {
    run.loop->step(run.loop->next_dt(dt0), dt0);
    fastest = std::max(fastest, run.fluid->max_flow_speed());
    worst = std::max(worst, std::abs(volume() / v0 - 1.0));
  }
  EXPECT_LE(worst, 0.01);
  EXPECT_LE(fastest, 3.0 * std::sqrt(2.0 * 9.81 * 1.0));
}

// Cut cells on a moving shell (issue #52): configs/verify/water_sloshing_cup (48 cells, a cup
// shaken sideways 2 cm at 1 Hz, water 0.1 m deep, never reaching the rim) with
// /fluid/water/cut_cells on (no particles: not on cut cells yet), 1 s: the cup's parts move
// every step and their water with them. The drift's bound is #52's (a thousandth of the water
// a second: a requirement, not a measurement); the water below the cup (the probe below_cup, read
// from F) within 5e-4 of the water: the issue asks none, and what reaches it is the first share's
// (the level set read across the bottom's rim gives slivers under it water; docs/cut-cells.md);
// nothing faster than 3 √(2 g H), H = 0.875 m the tank's height (the bound).
TEST(GridFluidShellsSlow, AShakenCupOnCutCellsKeepsItsWater) {
  auto run = load_on_cut_cells("water_sloshing_cup.json");
  const double dt0 = 1.0 / run.scene.time.fps;
  const double v0 = start_water_scene(run);
  const auto volume = [&] { return test::reported(*run.fluid, "water_volume"); };
  double worst = 0.0, below = 0.0, fastest = 0.0;
  while (run.loop->time() < 1.0 - 1e-9) {
    run.loop->step(run.loop->next_dt(dt0), dt0);
    worst = std::max(worst, std::abs(volume() / v0 - 1.0));
    below = std::max(below, test::reported(*run.fluid, "below_cup.water_volume"));
    fastest = std::max(fastest, run.fluid->max_flow_speed());
  }
  EXPECT_LE(worst, 1e-3);
  EXPECT_LE(below, 5e-4 * v0);
  EXPECT_LE(fastest, 3.0 * std::sqrt(2.0 * 9.81 * 0.875));
}

}  // namespace
}  // namespace shellflow::grid_fluid
