// Two-way coupling with the real plugins, as scenes load them (§5.1, §6): grid_fluid with
// mass_spring_cloth and bullet_rigid through the runtime's coupling loop.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "scratch_folder.hpp"
#include "shellflow/coupling/coupling_loop.hpp"
#include "shellflow/runtime/plugin_instance.hpp"
#include "shellflow/runtime/scene.hpp"
#include "shellflow/sdk/metrics.hpp"
#include "test_paths.hpp"

namespace shellflow::runtime {
namespace {

const std::filesystem::path kPlugins = shellflow::test_paths::plugin_dir();

/// The plugins of a scene and the §6 loop over them.
struct SceneRun {
  Scene scene;
  PluginInstance<sdk::FluidSolver> fluid;
  std::vector<PluginInstance<sdk::SolidSolver>> solids;
  std::unique_ptr<coupling::CouplingLoop> loop;

  explicit SceneRun(const std::filesystem::path& file) : scene(load_scene(file, {kPlugins})) {
    fluid = create_fluid(scene, *scene.fluid);
    std::vector<sdk::SolidSolver*> pointers;
    for (const auto& spec : scene.solids) {
      solids.push_back(create_solid(scene, spec));
      pointers.push_back(solids.back().get());
    }
    loop = std::make_unique<coupling::CouplingLoop>(
        fluid.get(), pointers, coupling::StepLimits{scene.time.cfl, scene.time.max_dt});
    loop->start(0.0, 1.0 / scene.time.fps);
  }
  void steps(int count) {
    for (int i = 0; i < count; ++i) loop->step(loop->next_dt(1e9), 1e9);
  }
};

/// The metric `key` as the fluid reports it now (a test failure, and NaN, if it has none).
double reported(const sdk::FluidSolver& fluid, const std::string& key) {
  sdk::Metrics m;
  fluid.report(m);
  for (const auto& [k, v] : m.values())
    if (k == key) return v;
  ADD_FAILURE() << "no metric '" << key << "'";
  return std::nan("");
}

/// The paper water scenes' two-way cloth (configs/paper/water_curtain.json and
/// water_cloth_funnel.json): mass_spring_cloth's stiff springs, pushed by the water.
constexpr const char* kPaperCloth =
    R"("stretch_stiffness": 2000, "stretch_damping": 2, "shear_stiffness": 200,
       "shear_damping": 0.2, "bending_stiffness": 0.001, "bending_damping": 1e-05,
       "receives_fluid_forces": true,)";

/// Momentum [kg m/s] and kinetic energy [J] of the shells: lumped node masses, a third of
/// each triangle's σ A per node (what the cloth uses; for a rigid shell the node sum of
/// m v is its momentum exactly, the energy a lumped approximation).
std::pair<Eigen::Vector3d, double> shell_momentum_energy(sdk::ShellSet shells) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double e = 0.0;
  for (const auto& s : shells) {
    Eigen::VectorXd mass = Eigen::VectorXd::Zero(s.node_count());
    const auto& T = *s.triangles;
    for (int t = 0; t < s.triangle_count(); ++t) {
      const Eigen::Vector3d a = s.positions.row(T(t, 0)), b = s.positions.row(T(t, 1)),
                            c = s.positions.row(T(t, 2));
      const double m = s.surface_density[t] * 0.5 * (b - a).cross(c - a).norm() / 3.0;
      for (int k = 0; k < 3; ++k) mass[T(t, k)] += m;
    }
    for (int i = 0; i < s.node_count(); ++i) {
      p += mass[i] * s.velocities.row(i).transpose();
      e += 0.5 * mass[i] * s.velocities.row(i).squaredNorm();
    }
  }
  return {p, e};
}

/// Momentum and kinetic energy of the fluid from its node velocities (density ρ).
std::pair<Eigen::Vector3d, double> fluid_momentum_energy(const sdk::FluidSolver& fluid,
                                                         double rho) {
  for (const auto& f : fluid.fields()) {
    if (f.name != "velocity") continue;
    const std::int64_t n = std::int64_t{f.dims[0]} * f.dims[1] * f.dims[2];
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    double e = 0.0;
    for (std::int64_t i = 0; i < n; ++i) {
      const Eigen::Vector3d u(f.data[0][i], f.data[1][i], f.data[2][i]);
      p += u;
      e += 0.5 * u.squaredNorm();
    }
    const double volume = rho * f.dx * f.dx * f.dx;
    return {p * volume, e * volume};
  }
  return {Eigen::Vector3d::Zero(), 0.0};
}

class TwoWayScenes : public shellflow::testing::ScratchFolder {
 protected:
  /// The cloth density sweep: a 0.5 m curtain of 7 × 7 nodes pinned along its top at
  /// x = 0.4 in `fluid` (the scene's fluid block), no gravity, σ from 1000× lighter to 1000×
  /// heavier than `reference` (ρΔx), at two step sizes, run for `steps` steps. Every run must
  /// stay finite, and its cloth below 20 m/s: ten times the 2 m/s stream of either sweep, no
  /// business of a cloth blown by it.
  void cloth_density_sweep(const std::string& fluid, double reference, int steps,
                           const char* what) {
    for (const double ratio : {1e-3, 1e-2, 1e-1, 1.0, 10.0, 100.0, 1000.0}) {
      for (const double max_dt : {0.005, 0.02}) {
        const auto file = write("sweep.json", R"({
          "gravity": [0, 0, 0], "time": {"fps": 24, "frames": 10, "max_dt": )" +
                                                  std::to_string(max_dt) + R"(, "cfl": 2.0},
          "coupling": {"max_speed": 20},
          "fluid": )" + fluid + R"(,
          "solids": [{"plugin": "mass_spring_cloth", "name": "curtain",
                      "mesh": {"type": "grid", "width": 0.5, "height": 0.5, "nodes_u": 7, "nodes_v": 7},
                      "transform": {"rotate_axis": [0, 1, 0], "rotate_deg": 90, "translate": [0.4, 0.5, 0.5]},
                      "surface_density": )" + std::to_string(ratio * reference) +
                                                  R"(, "pins": {"grid": ["top"]},
                      "collision": {"self_collision": false}}]})");
        SceneRun run(file);
        double max_speed = 0.0;
        bool finite = true;
        for (int step = 0; step < steps && finite; ++step) {
          run.steps(1);
          for (const auto& s : run.loop->shells()) {
            finite = finite && s.positions.allFinite() && s.velocities.allFinite();
            if (finite) max_speed = std::max(max_speed, s.velocities.rowwise().norm().maxCoeff());
          }
          finite = finite && !run.fluid->find_nonfinite();
        }
        std::printf("cloth in %s, sigma = %g rho dx, max_dt %g: %s, max node speed %.3g m/s\n",
                    what, ratio, max_dt, finite ? "finite" : "NOT FINITE", max_speed);
        EXPECT_TRUE(finite) << what << ", σ = " << ratio << " ρΔx, max_dt " << max_dt;
        EXPECT_LT(max_speed, 20.0) << what << ", σ = " << ratio << " ρΔx, max_dt " << max_dt;
      }
    }
  }
};
/// Its long runs: labelled slow (tests/CMakeLists.txt).
using TwoWayScenesSlow = TwoWayScenes;

TEST_F(TwoWayScenes, CurtainPinnedAtItsTopInStillAirStaysStill) {
  // No gravity, still air, a cloth at rest at its rest shape: nothing may move it. Any
  // spurious coupling force (a bias in the jump interpolation, a wrong right-hand side)
  // would. The answer is exactly 0; 1e-8 m/s is the issue's bound.
  const auto file = write("still.json", R"({
    "gravity": [0, 0, 0], "time": {"fps": 24, "frames": 10, "max_dt": 0.01},
    "fluid": {"plugin": "grid_fluid", "name": "air", "resolution": 16,
              "boundary": {"y_max": {"type": "open"}}},
    "solids": [{"plugin": "mass_spring_cloth", "name": "curtain",
                "mesh": {"type": "grid", "width": 0.6, "height": 0.6, "nodes_u": 9, "nodes_v": 9},
                "transform": {"rotate_axis": [0, 1, 0], "rotate_deg": 90, "translate": [0.5, 0.55, 0.5]},
                "surface_density": 0.1, "pins": {"grid": ["top"]}}]})");
  SceneRun run(file);
  run.steps(100);
  double max_speed = 0.0;
  for (const auto& s : run.loop->shells())
    max_speed = std::max(max_speed, s.velocities.rowwise().norm().maxCoeff());
  EXPECT_LE(max_speed, 1e-8);
}

TEST_F(TwoWayScenes, ClosedBoxWithClothAndRigidShellLosesEnergyAndReportsMomentum) {
  // A cloth and a rigid box shell thrown through a closed 1 m box of still air, no
  // gravity. Energy (fluid + solids) may only fall: the projection is an orthogonal
  // projection, semi-Lagrangian advection dissipates, and the coupling must not pump.
  // Momentum is not conserved here even in the exact equations: the walls push back on
  // the incompressible fluid (whose MAC momentum in a closed box is identically zero),
  // so the solids' momentum drains into the walls; the test prints its drift.
  const auto file = write("box.json", R"({
    "gravity": [0, 0, 0], "time": {"fps": 24, "frames": 10, "max_dt": 0.004},
    "fluid": {"plugin": "grid_fluid", "name": "air", "resolution": 16, "density": 1.0},
    "solids": [
      {"plugin": "mass_spring_cloth", "name": "cloth",
       "mesh": {"type": "grid", "width": 0.3, "height": 0.3, "nodes_u": 7, "nodes_v": 7},
       "transform": {"rotate_axis": [0, 1, 0], "rotate_deg": 90, "translate": [0.3, 0.5, 0.3]},
       "surface_density": 0.2},
      {"plugin": "bullet_rigid", "name": "rigid",
       "bodies": [{"name": "box", "mesh": {"type": "box", "size": [0.2, 0.2, 0.2], "divisions": 2},
                   "transform": {"translate": [0.6, 0.5, 0.65]}, "surface_density": 0.5,
                   "velocity": [-0.8, 0, 0]}]}]})");
  SceneRun run(file);
  const double e0 = shell_momentum_energy(run.loop->shells()).second;
  const Eigen::Vector3d p0 = shell_momentum_energy(run.loop->shells()).first;
  double e_max = 0.0;
  Eigen::Vector3d p_end;
  for (int step = 0; step < 500; ++step) {
    run.steps(1);
    const auto [ps, es] = shell_momentum_energy(run.loop->shells());
    const auto [pf, ef] = fluid_momentum_energy(*run.fluid, 1.0);
    ASSERT_TRUE(std::isfinite(es + ef)) << "step " << step;
    if (step >= 5) e_max = std::max(e_max, es + ef);  // after the unforced look-ahead
    p_end = ps + pf;
  }
  std::printf(
      "closed box, 500 steps: energy %.4g J at start, max %.4g J after step 5; "
      "momentum (%.3g, %.3g, %.3g) -> (%.3g, %.3g, %.3g) kg m/s\n",
      e0, e_max, p0.x(), p0.y(), p0.z(), p_end.x(), p_end.y(), p_end.z());
  // Measured: 0.6% above the start at step 5-ish (the node-sampled fluid energy and the
  // lumped rigid energy are estimates), then falling; bound 1%.
  EXPECT_LE(e_max, e0 * 1.01);
}

TEST_F(TwoWayScenesSlow, OpenBoatFloatsUntilAStreamFillsItThenSinksToTheFloor) {
  // Fig. 7 at test size: a Bullet boat_hull (0.6 m long, 0.3 m in the beam, 0.12 m deep,
  // 20 kg/m², 5 kg) dropped into 0.3 m of water floats on nothing but the §5.1 pressure
  // (its hull keeps the air out), and a stream from t = 0.5 s fills it: full of water it
  // weighs its own 5 kg more than the water around, and goes down to the ground plane.
  // The stream (2 cells in radius) loses water in flight, and the hull fills as fast as
  // what arrives: on the floor at 2.9 s while the Euler ray's gain in irrotational flow
  // offset that loss, at 3.3 s since φ is traced from the midpoint (6 Dec 2026).
  const auto file = write("boat.json", R"({
    "gravity": [0, -9.81, 0], "time": {"fps": 24, "frames": 72, "cfl": 0.9},
    "fluid": {"plugin": "grid_fluid", "name": "water", "resolution": 32,
      "water": {"initial": [{"type": "pool", "height": 0.3}],
        "sources": [{"shape": "cylinder", "from": [0.55, 0.9, 0.5], "to": [0.55, 1.0, 0.5],
                     "radius": 0.06, "velocity": [0, -1, 0], "start": 0.5}]}},
    "solids": [{"plugin": "bullet_rigid", "name": "boat",
      "bodies": [{"name": "hull",
        "mesh": {"type": "boat_hull", "length": 0.6, "beam": 0.3, "depth": 0.12,
                 "stations": 24, "sections": 12},
        "transform": {"translate": [0.5, 0.44, 0.5]}, "surface_density": 20.0}],
      "ground": {"height": 0.0}}]})");
  SceneRun run(file);
  const auto extent = [&] {
    const auto& x = run.loop->shells()[0].positions;
    return std::pair{x.col(1).minCoeff(), x.col(1).maxCoeff()};
  };
  double lowest_afloat = 1.0, highest_gunwale = 0.0;
  while (run.loop->time() < 3.5) {
    run.loop->step(run.loop->next_dt(1e9), 1e9);
    const auto [keel, gunwale] = extent();
    // Afloat: from when the splash of the drop has settled to when the stream lands.
    if (run.loop->time() > 0.3 && run.loop->time() < 0.7) {
      lowest_afloat = std::min(lowest_afloat, keel);
      highest_gunwale = std::max(highest_gunwale, gunwale);
    }
  }
  const auto [keel, gunwale] = extent();
  std::printf(
      "boat: afloat keel >= %.3f m, gunwale <= %.3f m (water at 0.3 m); at 3.5 s keel %.4f m, "
      "gunwale %.3f m\n",
      lowest_afloat, highest_gunwale, keel, gunwale);
  // Afloat its keel is far above the floor and its gunwale above the water (measured: the
  // keel no lower than 0.196 m, 10 cm under the water at the bottom of its first bob, of
  // its 12 cm of depth; a hull the water did not hold up would lie on the floor by then).
  EXPECT_GT(lowest_afloat, 0.15);
  EXPECT_GT(highest_gunwale, 0.3);
  // On the floor at the end: Bullet keeps the hull its collision margin (5 mm) above the
  // ground; Δx/4 more for the contact's settling. And all of it under water.
  EXPECT_LT(keel, 0.005 + 0.25 / 32.0);
  EXPECT_LT(gunwale, 0.3);
}

TEST_F(TwoWayScenesSlow, ALightCurtainInAWaterJetIsPushedAndTheWaterKept) {
  // Fig. 1 at test size (PhysBAM's Thin_Shells_Test_Water example 12 at 32 cells, 21 × 26
  // cloth nodes): a 4 m/s jet of water, 0.25 m in radius, onto a 2 × 2.5 m curtain of
  // 1 kg/m² hung by its top corners, walls on every side but the top, for 0.6 s (after
  // that the water on the floor is a layer thinner than these 12.5 cm cells). Water
  // pressure below the air's across the cloth used to pull the curtain back into the jet
  // (the lagged scheme's suction when a light shell outruns the water): forces of −1.6 kN
  // against the jet, and the mess destroyed 40 % of the water. The water must be what the
  // emitter gave (nothing leaves the tank), and the cloth no faster than the jet's water
  // can carry it. The jet is four cells across and its impact on the cloth comes down to a
  // step or two, so one run says little: it runs at four step sizes (CFL 0.7 … 1.0). The
  // level set alone: a cloth's cells carry one volume fraction for both its sides, which
  // lets a light cloth's water through it and gain energy (18.8 m/s here; #52).
  double fastest = 0.0, worst = 0.0, mean = 0.0;
  std::string figures;
  for (const double cfl : {0.7, 0.8, 0.9, 1.0}) {
    const auto file = write("curtain.json", R"({
      "gravity": [0, -9.81, 0], "time": {"fps": 60, "frames": 48, "cfl": )" +
                                                std::to_string(cfl) + R"(},
      "fluid": {"plugin": "grid_fluid", "name": "water", "resolution": 32,
        "domain": {"min": [-0.5, 0, 0.5], "max": [3.5, 4, 3.5]},
        "boundary": {"y_max": {"type": "open"}},
        "water": {"volume_fraction": false,
                  "sources": [{"shape": "cylinder", "from": [0, 2.6, 2], "to": [0.4, 2.6, 2],
                               "radius": 0.25, "velocity": [4, 0, 0]}]}},
      "solids": [{"plugin": "mass_spring_cloth", "name": "curtain",
        "mesh": {"type": "grid", "width": 2.0, "height": 2.5, "nodes_u": 21, "nodes_v": 26,
                 "pattern": "herringbone"},
        "transform": {"rotate_axis": [0, 1, 0], "rotate_deg": 90, "translate": [1.2, 2.75, 2.0]},
        "surface_density": 1.0, )" + std::string(kPaperCloth) +
                                                R"(
        "pins": {"grid": ["top_left", "top_right"]}}]})");
    SceneRun run(file);
    double cloth = 0.0;
    while (run.loop->time() < 0.6 - 1e-9) {
      run.loop->step(run.loop->next_dt(1e9), 1e9);
      for (const auto& s : run.loop->shells())
        cloth = std::max(cloth, s.velocities.rowwise().norm().maxCoeff());
    }
    // What the emitter gave (its fill and its held faces' flow: the volume budget) against
    // what the tank holds.
    const double volume = reported(*run.fluid, "water_volume");
    const double given = volume - reported(*run.fluid, "water_volume_drift");
    const double drift = (volume - given) / given;
    char line[96];
    std::snprintf(line, sizeof line, "%s%+.1f %% / %.1f m/s", figures.empty() ? "" : ", ",
                  100.0 * drift, cloth);
    figures += line;
    fastest = std::max(fastest, cloth);
    worst = std::max(worst, std::abs(drift));
    mean += std::abs(drift) / 4.0;
  }
  std::printf(
      "[  figure  ] curtain in a water jet, 0.6 s at CFL 0.7, 0.8, 0.9, 1.0: water against "
      "what the emitter gave, fastest cloth node: %s\n",
      figures.c_str());
  // The jet is 4 cells across, and in flight the level set alone loses some of it (figures:
  // docs/known-limits.md, "A jet that lands"). The bounds: the worst and the mean loss
  // measured on cells and half again.
  EXPECT_LT(worst, 0.40);
  EXPECT_LT(mean, 0.38);
  // The jet's water moves at 4 m/s; a cloth it pushes moves no faster than that water, save
  // for the elastic rebound of its free corners and the step in which the jet first meets
  // it, which the lagged coupling settles over a whole step (1/60 s here): measured at most
  // 9.8 m/s over the four step sizes (10.0 before the face fractions); 21 m/s with the
  // pull. The bound: the measured and half again.
  EXPECT_LT(fastest, 14.7);
}

TEST_F(TwoWayScenes, APoolOnAClothReleasedFromRestKeepsItsWaterFromTheFirstStep) {
  // A box of water 0.3 × 0.1 × 0.3 m at rest on a 0.7 m cloth pinned at its four corners
  // (32 cells, the level set alone), the two released together: the cloth sags under the
  // water. Before the first step the loop tells the fluid how the shells move over it
  // (FluidSolver::start): without that the water stood still for that step while the cloth
  // fell away beneath it, and the gap was refilled from the water's side (§3): +30 % of the
  // water in the first step, +27 % still at 1/12 s. Measured now: +8.1 % after the first
  // step (the cloth's first step is taken again under the water's pressure, and lands
  // elsewhere than the look-ahead that the water was given), +1.2 % at 1/12 s (+1.0 %
  // before φ's rays were traced from their midpoint, 6 Dec 2026, +2.0 % after it, +1.9 %
  // before the pressure solves' face fractions). The bounds: the larger and half again.
  const auto file = write("pool.json", R"({
    "gravity": [0, -9.81, 0], "time": {"fps": 24, "frames": 2, "cfl": 0.9},
    "fluid": {"plugin": "grid_fluid", "name": "water", "resolution": 32,
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
      "boundary": {"y_min": {"type": "open"}},
      "water": {"volume_fraction": false,
                "initial": [{"type": "box", "min": [0.35, 0.51, 0.35], "max": [0.65, 0.61, 0.65]}]}},
    "solids": [{"plugin": "mass_spring_cloth", "name": "cloth",
      "mesh": {"type": "grid", "width": 0.7, "height": 0.7, "nodes_u": 25, "nodes_v": 25,
               "pattern": "herringbone"},
      "transform": {"rotate_axis": [1, 0, 0], "rotate_deg": 90, "translate": [0.5, 0.5, 0.5]},
      "surface_density": 2.667, )" + std::string(kPaperCloth) +
                                           R"(
      "pins": {"grid": ["top_left", "top_right", "bottom_left", "bottom_right"]}}]})");
  SceneRun run(file);
  const auto drift = [&] {
    return reported(*run.fluid, "water_volume_change") /
           (reported(*run.fluid, "water_volume") - reported(*run.fluid, "water_volume_change"));
  };
  double first = 0.0;
  for (int frame = 1; frame <= 2; ++frame)
    while (frame / 24.0 - run.loop->time() > 1e-12) {
      const double left = frame / 24.0 - run.loop->time();
      const double dt = run.loop->next_dt(left);
      run.loop->step(dt, left - dt > 1e-12 ? left - dt : 1.0 / 24.0);
      if (first == 0.0) first = drift();
    }
  std::printf(
      "[  figure  ] pool on a cloth released from rest: water %+.1f %% after the first "
      "step, %+.1f %% at 1/12 s\n",
      100.0 * first, 100.0 * drift());
  EXPECT_LT(std::abs(first), 0.12);
  EXPECT_LT(std::abs(drift()), 0.03);
}

TEST_F(TwoWayScenes, ClothDensitySweepInAStreamStaysFinite) {
  // The issue's stress sweep on cloth: a curtain pinned along its top edge in a 2 m/s
  // stream, σ from 1000× lighter to 1000× heavier than ρΔx (the fluid mass per unit area of
  // one cell layer, 1/16 kg/m² here), at two step sizes. Measured: every combination stays
  // finite with bounded cloth speed (README table); the test asserts it.
  cloth_density_sweep(R"({"plugin": "grid_fluid", "name": "air", "resolution": 16,
                          "boundary": {"x_min": {"type": "inflow", "velocity": [2, 0, 0]},
                                       "x_max": {"type": "open"}}})",
                      1.0 / 16.0, 30, "air");
}

TEST_F(TwoWayScenesSlow, ClothInAWaterJetStaysFiniteOverTheDensitySweep) {
  // The cloth sweep above with water: a 2 m/s jet (no gravity, so that only the coupling
  // acts) onto a curtain pinned along its top edge, σ from 1000× lighter to 1000× heavier
  // than ρΔx (62.5 kg/m² at 16 cells), at two step sizes, 60 steps (the jet reaches the
  // cloth after 0.125 s). Every combination must stay finite, and the cloth below the
  // smoke sweep's bound, ten times the jet. The level set alone (the curtain's reason).
  cloth_density_sweep(R"({"plugin": "grid_fluid", "name": "water", "resolution": 16,
                          "water": {"volume_fraction": false,
                                    "sources": [{"shape": "cylinder", "from": [0, 0.6, 0.5],
                                                 "to": [0.15, 0.6, 0.5], "radius": 0.12,
                                                 "velocity": [2, 0, 0]}]}})",
                      1000.0 / 16.0, 60, "water");
}

}  // namespace
}  // namespace shellflow::runtime
