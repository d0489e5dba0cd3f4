// The particle level set (§4.4.2; Enright, Fedkiw, Ferziger, Mitchell 2002; Enright,
// Losasso, Fedkiw 2005) in grid_fluid's Liquid: Zalesak's slotted sphere in a rigid
// rotation keeps its volume far better with particles than with the level set alone,
// particles never cross a thin shell, moving or not, water particles keep their collision
// distance from it and do not close on it (§4.4.2), a layer on a shelf keeps its water,
// and save/restore gives the particles back bit for bit.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>

#include "grid_fluid_test_support.hpp"
#include "shellflow/grid_fluid/water/liquid.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

/// A Liquid from a "water" block, with the schema's defaults filled in.
std::unique_ptr<Liquid> make_liquid(nlohmann::json water, const grid::UniformGrid& grid,
                                    double fps) {
  runtime::SchemaValidator validator(".");
  validator.validate(water, Liquid::schema().json(), "");
  if (!validator.issues().empty())
    throw std::runtime_error("water params invalid at " + validator.issues().front().json_path);
  return std::make_unique<Liquid>(water, grid, Eigen::Vector3d::UnitY(), fps);
}

/// Zalesak's slotted sphere as in Enright et al. 2002, §5.3 (PhysBAM's 3D test): the box
/// [0, 100]^3, a sphere of radius 15 at (50, 75, 50) with a slot of width 5 cut from its
/// bottom 12.5 up (|x − 50| < 2.5, y < 72.5, through all z), rotating rigidly about the
/// z axis through (50, 50, 50) once in 628 s.
struct Zalesak {
  static constexpr double kPeriod = 628.0;
};

struct Revolution {
  double volume_start = 0.0, volume_end = 0.0;
  std::int64_t particles = 0;
};

/// Zalesak's sphere at `cells`^3, slotted unless `slotted` is false, turned `turns` of a
/// revolution by the prescribed rigid rotation at CFL 0.5 (φ and the particles follow the
/// exact face velocities; no projection: a pure transport test), on the level set alone
/// with `per_cell` particles; `advection` is the water block's φ step. A revolution is 100
/// frames, reseeded every 10 (the paper's scenes): ten times a turn.
Revolution turn_zalesak(int cells, int per_cell, const char* advection = "semi_lagrangian",
                        bool slotted = true, double turns = 1.0) {
  sdk::Context context;
  context.instance_name = "water";
  context.gravity = Eigen::Vector3d::Zero();
  context.fps = 100.0 / Zalesak::kPeriod;
  nlohmann::json initial = {{{"type", "sphere"}, {"center", {50, 75, 50}}, {"radius", 15}}};
  if (slotted)
    initial.push_back(
        {{"type", "box"}, {"min", {47.5, 0, -1}}, {"max", {52.5, 72.5, 101}}, {"subtract", true}});
  GridFluid fluid(
      test::validated(
          {{"domain", {{"min", {0, 0, 0}}, {"max", {100, 100, 100}}}},
           {"resolution", cells},
           {"water", test::water_core("cells", {{"initial", std::move(initial)},
                                                {"advection", advection},
                                                {"particles", {{"per_cell", per_cell}}}})},
           {"prescribed_velocity",
            {{"type", "rigid_rotation"}, {"center", {50, 50, 50}}, {"period", Zalesak::kPeriod}}}}),
      context);
  Revolution out;
  out.volume_start = fluid.liquid()->level_set().volume();
  const double end = turns * Zalesak::kPeriod;
  double t = 0.0;
  while (t < end - 1e-9) {
    const double dt = std::min(fluid.stable_dt(0.5), end - t);
    fluid.advect(t, dt, {}, {});
    fluid.project(dt, {}, {});
    t += dt;
  }
  out.volume_end = fluid.liquid()->level_set().volume();
  out.particles = fluid.liquid()->particles().size();
  return out;
}

TEST(LevelSetAdvection, ASphereTurningRigidlyKeepsItsVolume) {
  // Zalesak's sphere without its slot at 32^3 (r = 4.8Δx), one revolution (290 steps, each
  // reinitialised), the level set alone. The trilinear step loses it all (measured -100%);
  // MacCormack's step kept it within 2% (+1.6%) once fast marching stopped dividing the
  // interface nodes by a |∇φ| that central differences understate on a curved surface
  // (3% at this radius; it grew the sphere by 45%). Bound: 5% of the volume.
  const Revolution trilinear = turn_zalesak(32, 0, "semi_lagrangian", false);
  const Revolution maccormack = turn_zalesak(32, 0, "maccormack", false);
  const double change_trilinear = trilinear.volume_end / trilinear.volume_start - 1.0;
  const double change_maccormack = maccormack.volume_end / maccormack.volume_start - 1.0;
  std::printf("[  figure  ] sphere turning rigidly, 32^3, one revolution, level set alone: "
              "volume %+.1f%% trilinear, %+.1f%% MacCormack\n",
              100.0 * change_trilinear, 100.0 * change_maccormack);
  EXPECT_LT(change_trilinear, -0.5);  // the case tells the schemes apart
  EXPECT_LT(std::abs(change_maccormack), 0.05);
}

TEST(ParticleLevelSetSlow, ZalesakSphereKeepsItsVolumeWithParticles) {
  // The issue's 50^3 suite version of Zalesak's test (the 100^3 one is a bench case).
  // Enright et al. 2002 (their table 3, 100^3): the particle level set keeps the slotted
  // sphere's volume to a few per cent where the level set alone loses a large part of it;
  // here at half their resolution the slot is 2.5 cells wide (measured: -99.6% alone,
  // -6.2% with particles; with MacCormack's φ step +11%, the slot partly filling, and -1.0%).
  const Revolution alone = turn_zalesak(50, 0);
  const Revolution particles = turn_zalesak(50, 16);
  const double loss_alone = 1.0 - alone.volume_end / alone.volume_start;
  const double loss_particles = 1.0 - particles.volume_end / particles.volume_start;
  RecordProperty("volume_loss_level_set_alone", std::to_string(loss_alone));
  RecordProperty("volume_loss_particle_level_set", std::to_string(loss_particles));
  std::printf(
      "[  figure  ] Zalesak 50^3, one revolution: volume loss %.2f%% alone, %.2f%% with "
      "16 particles per cell (%ld particles)\n",
      100.0 * loss_alone, 100.0 * loss_particles, static_cast<long>(particles.particles));
  EXPECT_GT(particles.particles, 0);
  EXPECT_LT(std::abs(loss_particles), 0.25 * std::abs(loss_alone));
}

TEST(ParticleLevelSet, ZalesaksSphereKeepsInAQuarterTurnTheWaterTheLevelSetAloneLoses) {
  // §4.4.2 (Enright et al. 2002) on cell-centred φ: the particles' corrections reach the
  // cell centres about them. The trilinear step alone rounds the slot's edges away every
  // step (the slot is 1.6 cells wide at 32^3); the particles give them back. Bound: with
  // particles, under a third of the level set's loss alone, which must itself be more than
  // 5 % so that the comparison can fail (the figures: docs/measured-figures.md).
  const Revolution alone = turn_zalesak(32, 0, "semi_lagrangian", true, 0.25);
  const Revolution with = turn_zalesak(32, 16, "semi_lagrangian", true, 0.25);
  const double change_alone = alone.volume_end / alone.volume_start - 1.0;
  const double change_with = with.volume_end / with.volume_start - 1.0;
  std::printf(
      "[  figure  ] Zalesak 32^3, a quarter turn: %+.2f%% alone, %+.2f%% with 16 "
      "particles per cell\n",
      100.0 * change_alone, 100.0 * change_with);
  EXPECT_LT(change_alone, -0.05);  // the level set alone does lose it: the test can tell
  EXPECT_LT(std::abs(change_with), std::abs(change_alone) / 3.0);
}

/// A thin plate x = `x` spanning the tank (a little beyond its walls) seals it.
sdk::ShellSurface dam_plate(double x, double speed) {
  auto plate = test::make_plate({x, 0.5, 0.5}, Eigen::Vector3d::UnitX(), 1.2, 9);
  plate.velocities.col(0).setConstant(speed);
  return plate;
}

nlohmann::json dam_params(double water_x, double height = 0.8) {
  return {{"resolution", 16},
          {"pressure", {{"tolerance", 1e-6}}},
          {"water",
           {{"particles", {{"per_cell", 16}}},
            {"initial",
             {{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {water_x, height, 2}}}}}}}};
}

/// What a run of the thin-wall dam saw on the plate's dry side, worst over its steps.
struct DamRun {
  int water_particles_beyond = 0;  ///< water particles with x beyond the plate
  int wet_samples_beyond = 0;      ///< φ samples <= 0 more than Δx beyond it
  int water_particles_near = 0;    ///< water particles within Δx before it (not vacuous)
};

/// The thin-wall dam with particles, the plate moving at `speed` from x0, for `duration`
/// at the CFL step.
DamRun run_dam(GridFluid& f, double x0, double speed, double duration) {
  double x = x0, t = 0.0;
  DamRun worst;
  const double dx = f.grid().dx();
  while (t < duration - 1e-12) {
    const double dt = std::min(f.stable_dt(0.9), duration - t);
    const std::vector<sdk::ShellSurface> s0{dam_plate(x, speed)},
        s1{dam_plate(x + speed * dt, speed)};
    f.advect(t, dt, s0, s1);
    const std::vector<sdk::Positions> v_eff{s1[0].velocities};
    f.project(dt, s1, v_eff);
    x += speed * dt;
    t += dt;
    const ParticleLevelSet& p = f.liquid()->particles();
    int beyond = 0, near = 0;
    for (std::int64_t i = 0; i < p.size(); ++i)
      if (p.sign(i) < 0) {
        beyond += p.position(i).x() > x ? 1 : 0;
        near += p.position(i).x() > x - dx && p.position(i).x() <= x ? 1 : 0;
      }
    const LevelSet& level_set = f.liquid()->level_set();
    const auto& phi = level_set.phi();
    int wet = 0;
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i)
      wet += phi[i] <= 0.0 && level_set.grid().position(Location::Node, i).x() > x + dx ? 1 : 0;
    worst.water_particles_beyond = std::max(worst.water_particles_beyond, beyond);
    worst.wet_samples_beyond = std::max(worst.wet_samples_beyond, wet);
    worst.water_particles_near = std::max(worst.water_particles_near, near);
  }
  return worst;
}

TEST(ParticleLevelSetSlow, WaterSloshingAgainstASealingPlateNeverReachesTheDrySide) {
  // The issue's sealed tank: a column x < 0.25, 0.8 high, collapses onto a plate that
  // seals the 16^3 tank at x = 0.5 + Δx/3 (between node planes), hits it at about 1.5 m/s
  // and runs up it, for 1 s; the plate still, then moving into the water at 0.05 m/s.
  // Exact: no water particle beyond the plate and no water sample of φ more than Δx beyond it
  // after any step (the level set's own dam test's bound).
  for (const double speed : {0.0, -0.05}) {
    auto fluid = test::make_fluid(dam_params(0.25));
    const DamRun run = run_dam(*fluid, 0.5 + fluid->grid().dx() / 3.0, speed, 1.0);
    EXPECT_EQ(run.water_particles_beyond, 0) << "plate speed " << speed;
    EXPECT_EQ(run.wet_samples_beyond, 0) << "plate speed " << speed;
    EXPECT_GT(run.water_particles_near, 0) << "plate speed " << speed;  // it reached the plate
  }
}

/// Water x < 0.5 up to y = 0.6 with 16 particles per cell in a 16^3 tank, and a still
/// plate spanning it at x = 0.5 + Δx/3 (between node planes), with its band.
struct WaterAgainstAPlate {
  grid::UniformGrid grid{Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i::Constant(16)};
  double plate_x = 0.5 + grid.dx() / 3.0;
  std::vector<sdk::ShellSurface> shells{dam_plate(plate_x, 0.0)};
  ShellGeometry plate{shells, 1e-3 * grid.dx()};
  geometry::ShellBand band{grid};
  std::unique_ptr<Liquid> liquid = make_liquid(
      test::water_core(  // the level set alone: F's flux through a shell needs the
                         // projection's apertures, which these steps leave out
          "cells",
          {{"particles", {{"per_cell", 16}}},
           {"initial", {{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.5, 0.6, 2}}}}}}),
      grid, 24.0);
  WaterAgainstAPlate() { band.add(geometry::TriangleMesh(shells.front()), 3.0 * grid.dx()); }
  /// One step of the water's phases at the still plate with the face velocities `faces`,
  /// ending at t_end.
  void step(const MacGrid& faces, double dt, double t_end) {
    liquid->advect(0.0, faces, dt, faces.max_face_speed(), plate, &band);
    liquid->refill({}, dt, plate, plate);
    liquid->reinitialize(plate, plate, &band, t_end);
  }
  /// The face velocities 1 m/s along +x where `moving` (a face's centre) holds, else 0.
  MacGrid driven(const std::function<bool(const Eigen::Vector3d&)>& moving =
                     [](const Eigen::Vector3d&) { return true; }) const {
    MacGrid faces(grid);
    auto& u = faces.face_velocity(0);
    for (std::int64_t f = 0; f < static_cast<std::int64_t>(u.size()); ++f)
      u[f] = moving(grid.position(Location::FaceX, f)) ? 1.0 : 0.0;
    return faces;
  }
};

TEST(ParticleLevelSet, WaterParticlesDrivenAtAPlateStayOnTheirSide) {
  // §4.4.2: a path that crosses a shell is stopped on its own side. Water x < 0.5 driven at
  // 1 m/s into a plate at x = 0.5 + Δx/3 (16^3, steps of 0.9Δx): the velocity at a particle
  // next to the plate is half the water's (the object's, 0, behind it), enough to carry it
  // through in a step; none ever lies beyond the plate. Exact: a count.
  WaterAgainstAPlate w;
  ASSERT_GT(w.liquid->particles().size(), 0);
  const MacGrid faces = w.driven();
  const double dt = 0.9 * w.grid.dx();
  int beyond = 0, near = 0;
  for (int s = 0; s < 8; ++s) {
    w.step(faces, dt, (s + 1) * dt);
    const ParticleLevelSet& p = w.liquid->particles();
    for (std::int64_t i = 0; i < p.size(); ++i)
      if (p.sign(i) < 0) {
        beyond += p.position(i).x() > w.plate_x ? 1 : 0;
        near += p.position(i).x() > w.plate_x - 0.5 * w.grid.dx() ? 1 : 0;
      }
  }
  EXPECT_EQ(beyond, 0);
  EXPECT_GT(near, 0);  // not vacuous: water particles were pressed against the plate
}

TEST(ParticleLevelSet, WaterParticlesKeepTheirCollisionDistanceFromAShell) {
  // §4.4.2: a water particle nearer a shell than its collision distance is moved out along
  // the normal. The water of the test above driven at 1 m/s into the plate for 8 steps:
  // after each step every water particle lies at least its own collision distance from
  // the plate's plane (to 1e-9Δx, the round-off of the move), while the paths alone would
  // leave them within ε of it.
  WaterAgainstAPlate w;
  const MacGrid faces = w.driven();
  const double dt = 0.9 * w.grid.dx();
  double worst = std::numeric_limits<double>::infinity();
  std::int64_t kept_off = 0;
  for (int s = 0; s < 8; ++s) {
    w.step(faces, dt, (s + 1) * dt);
    kept_off += w.liquid->particles().stats().kept_off_shells;
    const ParticleLevelSet& p = w.liquid->particles();
    for (std::int64_t i = 0; i < p.size(); ++i)
      if (p.sign(i) < 0) {
        const double d = (w.plate_x - p.position(i).x()) - p.collision_distance(i);
        worst = std::min(worst, d);
      }
  }
  EXPECT_GE(worst, -1e-9 * w.grid.dx());
  EXPECT_GT(kept_off, 0);  // not vacuous: particles were moved out
}

TEST(ParticleLevelSet, WaterParticlesNearAShellDoNotCloseOnIt) {
  // §4.4.2: a water particle within its collision distance of an object has the normal
  // component of its velocity clamped to at least the object's. Water up to y = 0.6 is
  // driven into a still plate (x = 0.5 + Δx/3): the faces x < 0.47, y <= 0.5 move at
  // 1 m/s, the rest are still. A particle is known again by its collision distance (a
  // random draw). The first seeding ignores the plate, so some water particles start
  // within their collision distance of it: in one advection step of 0.5Δx none of those
  // gets nearer (to round-off), where unclamped they would close by up to the step.
  WaterAgainstAPlate w;
  const MacGrid faces =
      w.driven([](const Eigen::Vector3d& x) { return x.y() <= 0.5 && x.x() < 0.47; });
  const ParticleLevelSet& p = w.liquid->particles();
  std::map<double, double> before;  // collision distance -> distance to the plate
  for (std::int64_t i = 0; i < p.size(); ++i)
    if (p.sign(i) < 0) before[p.collision_distance(i)] = w.plate_x - p.position(i).x();
  w.liquid->advect(0.0, faces, 0.5 * w.grid.dx(), faces.max_face_speed(), w.plate, &w.band);
  int near = 0;
  double worst = std::numeric_limits<double>::infinity();
  for (std::int64_t i = 0; i < p.size(); ++i) {
    const auto it = before.find(p.collision_distance(i));
    if (p.sign(i) > 0 || it == before.end() || it->second >= it->first ||
        p.position(i).y() > 0.45)
      continue;
    ++near;
    worst = std::min(worst, (w.plate_x - p.position(i).x()) - it->second);
  }
  EXPECT_GT(near, 0);  // not vacuous
  EXPECT_GE(worst, -1e-12);
}

TEST(ParticleLevelSet, AShellSweepingOverStillParticlesPushesWaterAndDeletesAir) {
  // §4.4.2: paths are tested against the moving shell. Still water (no velocity) up to
  // y = 0.6 with its particles; a plate spanning the tank at x = 0.3 moves +x at 0.6Δx
  // per step for 10 steps (6Δx). The particles do not move, so only the swept test sees
  // the plate pass over them: afterwards no particle of either sign lies in the strip the
  // plate swept (water pushed ahead of it, air deleted), where the segment tests at n and
  // at n+1 left every one. Exact: a count.
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i::Constant(16));
  const double dx = grid.dx(), x0 = 0.3 + dx / 3.0, step = 0.6 * dx;
  auto liquid = make_liquid(
      test::water_core(
          "cells", {{"particles", {{"per_cell", 16}}},
                    {"initial", {{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {2, 0.6, 2}}}}}}),
      grid, 24.0);
  const MacGrid still(grid);
  const auto in_strip = [&](double from, double to, int sign) {
    const ParticleLevelSet& p = liquid->particles();
    int count = 0;
    for (std::int64_t i = 0; i < p.size(); ++i)
      if (p.sign(i) == sign && p.position(i).x() > from && p.position(i).x() < to) ++count;
    return count;
  };
  const double x_end = x0 + 10 * step;
  const int water_before = in_strip(x0, x_end, -1), air_before = in_strip(x0, x_end, 1);
  const int water_ahead = in_strip(x_end, 2.0, -1);
  for (int s = 0; s < 10; ++s) {
    const std::vector<sdk::ShellSurface> s0{dam_plate(x0 + s * step, 0.0)},
        s1{dam_plate(x0 + (s + 1) * step, 0.0)};
    const ShellGeometry g0(s0, 1e-3 * dx), g1(s1, 1e-3 * dx);
    geometry::ShellBand band(grid);
    band.add_swept(geometry::TriangleMesh(s0.front()), geometry::TriangleMesh(s1.front()),
                   3.0 * dx);
    liquid->advect(0.0, still, 0.01, 0.0, g0, &band);
    liquid->refill({}, 0.01, g0, g1);
    liquid->reinitialize(g0, g1, &band, 0.01 * (s + 1));  // 0.1 s: before the first reseed
  }
  EXPECT_GT(water_before, 0);  // not vacuous: the strip held particles of both signs
  EXPECT_GT(air_before, 0);
  EXPECT_EQ(in_strip(x0 + 1e-9, x_end, -1), 0);
  EXPECT_EQ(in_strip(x0 + 1e-9, x_end, 1), 0);
  // The strip's water was pushed ahead of the plate, not deleted: at least half of it is
  // there now (a particle is deleted only where its corrected path still crosses, here at
  // the plate's edges against the walls).
  EXPECT_GE(in_strip(x_end, 2.0, -1) - water_ahead, water_before / 2);
}

/// A block of water 0.3 × 0.1 m (3.2Δx high) across the depth of a 1 × 0.5 × 0.25 m tank
/// at 32 cells, on a shelf that spans the tank at y = 0.2104 (a third of a cell above a
/// node plane), air beneath. It spreads into a layer about a cell thick; returns the
/// relative volume change after `duration`.
double water_spreading_on_a_shelf(int per_cell, double duration) {
  auto fluid = test::make_fluid(
      {{"domain", {{"min", {0, 0, 0}}, {"max", {1.0, 0.5, 0.25}}}},
       {"resolution", 32},
       {"pressure", {{"tolerance", 1e-5}}},
       {"water",
        {{"particles", {{"per_cell", per_cell}}},
         {"initial",
          {{{"type", "box"}, {"min", {0.35, 0.2104, -1}}, {"max", {0.65, 0.3104, 2}}}}}}}});
  const std::vector<sdk::ShellSurface> shells{
      test::make_plate({0.5, 0.2104, 0.125}, Eigen::Vector3d::UnitY(), 1.2, 13)};
  const std::vector<sdk::Positions> v_eff{shells.front().velocities};
  const double v0 = fluid->liquid()->level_set().volume();
  test::run_for(*fluid, duration, shells, v_eff);
  return (fluid->liquid()->level_set().volume() - v0) / v0;
}

TEST(ParticleLevelSetSlow, WaterSpreadingOnAShelfKeepsThreeFifthsOfItAloneAndWithParticles) {
  // A block of water spreading into a film on a shelf that spans the tank, between node
  // planes. The particle level set issue asks 5 % here; unmet: a film thinner than the
  // shelf's distance to the next node plane has no wet node, and its particles escape
  // (README, Known limits). Measured with the sharp volume: −26.4% alone, −31.4% with 16
  // particles per cell. Before the block's underside on the shelf stopped being a surface
  // to its first φ (its node above the shelf held that distance, and the layer read short
  // whenever it moved by a cell): −37.2% and −35.2%, when §4.4.2's claim, "properly
  // colliding negative particles against objects significantly improves the ability to
  // properly resolve thin films", held here; it no longer does. Bound: 40 % lost either
  // way (the particle runs differ a little with the number of threads).
  const double alone = water_spreading_on_a_shelf(0, 1.5);
  const double particles = water_spreading_on_a_shelf(16, 1.5);
  std::printf("[  figure  ] layer spreading on a shelf, 32 cells, 1.5 s: volume %+.2f%% alone, "
              "%+.2f%% with 16 particles per cell\n",
              100.0 * alone, 100.0 * particles);
  RecordProperty("volume_change_alone", std::to_string(alone));
  RecordProperty("volume_change_particles", std::to_string(particles));
  EXPECT_GT(alone, -0.4);
  EXPECT_GT(particles, -0.4);
}

TEST(ParticleLevelSetSlow, StillPoolCutByATiltedPlateStaysNearlyStillWithParticles) {
  // The water core's still pool pierced by a static tilted plate (water_test) with 16
  // particles per cell, 200 steps of 0.01 s. Water particles kept their collision distance
  // off the plate must not be moved out of the water: pushed above the surface they became
  // escaped particles that made water in the air, and the pool stirred at 0.11 m/s. Seeded
  // at construction about φ built without the plate, their correction then stirred it at
  // up to 0.03 m/s; they are seeded again at the first step, about φ marched among the
  // shells and kept off them, and the pool stays still: measured 2.6e-12 m/s (the level
  // set alone, below 1e-8 m/s: water_test). The bound: 1e-6 m/s.
  auto fluid = test::make_fluid({{"resolution", 16},
                                 {"pressure", {{"tolerance", 1e-10}}},
                                 {"water",
                                  {{"particles", {{"per_cell", 16}}},
                                   {"initial", {{{"type", "pool"}, {"height", 0.41}}}}}}});
  const auto plate =
      test::make_plate({0.5, 0.45, 0.52}, Eigen::Vector3d(1.0, 0.3, -0.4).normalized(), 0.6, 7);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v_eff{plate.velocities};
  double t = 0.0, fastest = 0.0;
  for (int s = 0; s < 200; ++s) {
    fluid->advect(t, 0.01, shells, shells);
    fluid->project(0.01, shells, v_eff);
    t += 0.01;
    fastest = std::max(fastest, fluid->mac().max_face_speed());
  }
  std::printf("[  figure  ] still pool, tilted plate, 16 particles per cell: max |u| %.1e m/s\n",
              fastest);
  EXPECT_LT(fastest, 1e-6);
}

TEST(ParticleLevelSet, EmittedWaterGetsParticlesAsItIsEmitted) {
  // A stream into an empty tank: its water has water particles from its first step, long
  // before the first reseeding (frame 10 at 24 fps, t = 0.42 s), and every one of them
  // lies in water or within the band of it.
  auto fluid = test::make_fluid({{"resolution", 16},
                                 {"water",
                                  {{"particles", {{"per_cell", 8}}},
                                   {"sources",
                                    {{{"shape", "cylinder"},
                                      {"from", {0.5, 0.8, 0.5}},
                                      {"to", {0.5, 0.9, 0.5}},
                                      {"radius", 0.1},
                                      {"velocity", {0.0, -1.0, 0.0}}}}}}}});
  EXPECT_EQ(fluid->liquid()->particles().size(), 0);
  double t = 0.0;
  const double dt = 0.02;
  for (int s = 0; s < 5; ++s) {
    fluid->advect(t, dt, {}, {});
    fluid->project(dt, {}, {});
    t += dt;
  }
  const ParticleLevelSet& p = fluid->liquid()->particles();
  const LevelSet& phi = fluid->liquid()->level_set();
  int water = 0;
  for (std::int64_t i = 0; i < p.size(); ++i) {
    if (p.sign(i) > 0) continue;
    ++water;
    EXPECT_LE(phi.sample(p.position(i)), 3.0 * fluid->grid().dx()) << "particle " << i;
  }
  EXPECT_GT(water, 0);
}

TEST(ParticleLevelSet, SaveAndRestoreGiveTheSameRunBitForBit) {
  // The coupling loop rewinds (§4.3, §6): a step from a restored state must repeat the
  // step from the saved one exactly, particles included.
  auto fluid = test::make_fluid(dam_params(0.52));
  const double dx = fluid->grid().dx();
  run_dam(*fluid, 0.5 + dx / 3.0, 0.0, 0.2);
  sdk::StateBuffer saved;
  sdk::StateWriter writer(saved);
  fluid->save(writer);
  const auto step = [&] {
    const std::vector<sdk::ShellSurface> s{dam_plate(0.5 + dx / 3.0, 0.0)};
    const std::vector<sdk::Positions> v_eff{s[0].velocities};
    fluid->advect(0.2, 0.01, s, s);
    fluid->project(0.01, s, v_eff);
  };
  step();
  const ParticleLevelSet first = fluid->liquid()->particles();
  const std::vector<double> phi = fluid->liquid()->level_set().phi();
  sdk::StateReader reader(saved);
  fluid->restore(reader);
  step();
  const ParticleLevelSet& second = fluid->liquid()->particles();
  ASSERT_EQ(first.size(), second.size());
  ASSERT_GT(first.size(), 0);
  for (std::int64_t i = 0; i < first.size(); ++i) {
    ASSERT_EQ(first.position(i), second.position(i)) << "particle " << i;
    ASSERT_EQ(first.radius(i), second.radius(i)) << "particle " << i;
    ASSERT_EQ(first.sign(i), second.sign(i)) << "particle " << i;
  }
  EXPECT_EQ(phi, fluid->liquid()->level_set().phi());
}


/// Water below y = `surface`: φ the signed distance, clamped to the band.
void fill_below(LevelSet& level_set, double surface) {
  auto& phi = level_set.phi();
  const grid::UniformGrid& grid = level_set.grid();
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i)
    phi[i] = std::clamp(grid.position(Location::Node, i).y() - surface, -level_set.band(),
                        level_set.band());
}

TEST(ParticleLevelSet, WaterParticlesDrivenAtAWallStopTheirCollisionDistanceOffIt) {
  // A water particle that reached a wall's plane and stayed on it held a film of water there
  // (a thin tank's splash coated its walls and ceiling). Water below y = 0.2, every side a
  // wall, driven down at 1 m/s for
  // 0.2 s (3.2 cells): each water particle stops no nearer the floor than its collision
  // distance, or than it already was, and never nearer than 0.1Δx; those that do not come
  // near move exactly Δt u.
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i::Constant(16));
  const double dx = grid.dx();
  ParticleLevelSet particles({{"per_cell", 8}, {"reseed_every", 10}, {"seed", 0}}, grid, 24.0);
  std::array<bool, 6> walls;
  walls.fill(true);
  particles.set_walls(walls);
  LevelSet level_set(grid, 6.0 * dx);
  fill_below(level_set, 0.2);
  const ShellGeometry none;
  particles.seed(level_set, none);
  NodeFields nodes(level_set.grid(), 0.0, false);  // on the particles' lattice
  std::fill(nodes.velocity(1).begin(), nodes.velocity(1).end(), -1.0);
  const double dt = 0.01;
  std::int64_t stopped = 0, free = 0;
  for (int step = 0; step < 20; ++step) {
    std::vector<Eigen::Vector3d> before(particles.size());
    for (std::int64_t i = 0; i < particles.size(); ++i) before[i] = particles.position(i);
    particles.advect(nodes, dt, none, nullptr);
    ASSERT_EQ(particles.size(), static_cast<std::int64_t>(before.size()));  // none deleted
    for (std::int64_t i = 0; i < particles.size(); ++i) {
      if (particles.sign(i) > 0) continue;
      const double y0 = before[i].y(), y1 = particles.position(i).y();
      const double keep =
          std::max(std::min(particles.collision_distance(i), y0), 0.1 * dx);
      if (y0 - dt > keep) {
        EXPECT_NEAR(y1, y0 - dt, 1e-12) << "particle " << i;  // round-off of x + Δt u
        ++free;
      } else {
        EXPECT_NEAR(y1, keep, 1e-12) << "particle " << i;
        ++stopped;
      }
      EXPECT_GE(y1, 0.1 * dx - 1e-15) << "particle " << i;
    }
  }
  EXPECT_GT(stopped, 1000);  // not vacuous: the whole layer reached the floor
  EXPECT_GT(free, 1000);
}

TEST(ParticleLevelSet, AirParticlesCoveredByWaterAreDroppedNotKept) {
  // The pressure keeps no bubble: an air particle left deep in water carved the same pocket
  // every step that the flow closed again (a thin tank's dam break lost 17 % in 2 s). The
  // surface at y = 0.5 rises to 0.6: every air particle now more than 1.5 radii under it is
  // deleted by adjust() (PhysBAM's radius_fraction), and none becomes spray (water particles
  // now deeper than the band go as always).
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i::Constant(16));
  const double dx = grid.dx();
  ParticleLevelSet particles({{"per_cell", 8}, {"reseed_every", 10}, {"seed", 0}}, grid, 24.0);
  LevelSet level_set(grid, 6.0 * dx);
  fill_below(level_set, 0.5);
  const ShellGeometry none;
  particles.seed(level_set, none);
  fill_below(level_set, 0.6);
  std::int64_t air = 0, drowned = 0, deep = 0;  // deep: water now beyond the 3Δx band
  for (std::int64_t i = 0; i < particles.size(); ++i) {
    if (particles.sign(i) < 0) {
      deep += 0.6 - particles.position(i).y() > 3.0 * dx ? 1 : 0;
      continue;
    }
    ++air;
    drowned += 0.6 - particles.position(i).y() > 1.5 * particles.radius(i) ? 1 : 0;
  }
  ASSERT_GT(drowned, 500);  // not vacuous
  ASSERT_LT(drowned, air);   // and not all of them
  const std::int64_t before = particles.size();
  particles.adjust(level_set, none);
  EXPECT_EQ(before - particles.size(), drowned + deep);
  EXPECT_EQ(particles.stats().removed, 0);
  EXPECT_EQ(particles.spray().size(), 0);
  for (std::int64_t i = 0; i < particles.size(); ++i) {
    if (particles.sign(i) > 0) {
      EXPECT_LE(0.6 - particles.position(i).y(), 0.75 * dx) << "particle " << i;  // 1.5 r_max
    }
  }
}

TEST(ParticleLevelSet, RemovedWaterParticlesFlyAsSprayUntilTheyLand) {
  // Water below y = 0.5 (16^3) seeded with particles, one step at u = (0.5, 0, 0); then the
  // surface is dropped to y = 0.2: every water particle now more than Δx above it is removed
  // from the level set and becomes a spray drop with its path's velocity. A step later each
  // drop has fallen freely (exact for constant gravity); when the water rises over them,
  // they have all landed.
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i::Constant(16));
  const double dx = grid.dx();
  const Eigen::Vector3d gravity(0.0, -9.81, 0.0);
  ParticleLevelSet particles({{"per_cell", 8}, {"reseed_every", 10}, {"seed", 0}}, grid, 24.0,
                             gravity);
  LevelSet level_set(grid, 6.0 * dx);
  fill_below(level_set, 0.5);
  const ShellGeometry none;
  particles.seed(level_set, none);
  NodeFields nodes(level_set.grid(), 0.0, false);  // on the particles' lattice
  std::fill(nodes.velocity(0).begin(), nodes.velocity(0).end(), 0.5);
  const double dt = 0.01;
  particles.advect(nodes, dt, none, nullptr);
  fill_below(level_set, 0.2);
  std::int64_t expected = 0;  // water particles more than Δx above the new surface
  for (std::int64_t i = 0; i < particles.size(); ++i)
    expected += particles.sign(i) < 0 && particles.position(i).y() - 0.2 > dx ? 1 : 0;
  ASSERT_GT(expected, 100);  // not vacuous
  // Before adjust(): the escaped water particles (above the surface by more than their
  // radius) as writers see them, with the velocity at each.
  ParticleArrays escaped;
  particles.gather(-1, nodes, none, nullptr, escaped, &level_set);
  std::int64_t above_by_radius = 0;
  for (std::int64_t i = 0; i < particles.size(); ++i)
    above_by_radius += particles.sign(i) < 0 &&
                               particles.position(i).y() - 0.2 > particles.radius(i)
                           ? 1
                           : 0;
  EXPECT_EQ(escaped.size(), above_by_radius);
  EXPECT_GE(escaped.size(), expected);
  for (std::int64_t i = 0; i < escaped.size(); ++i)
    EXPECT_NEAR(escaped.u(i).x(), 0.5, 1e-12);  // trilinear weights sum to 1 up to round-off
  particles.adjust(level_set, none);
  const ParticleArrays& spray = particles.spray();
  EXPECT_EQ(spray.size(), expected);
  EXPECT_EQ(particles.stats().removed, expected);
  // The path's velocity is the trilinear lattice velocity, uniform: exact to round-off.
  constexpr double kRoundOff = 1e-12;
  for (std::int64_t i = 0; i < spray.size(); ++i) {
    EXPECT_NEAR((spray.u(i) - Eigen::Vector3d(0.5, 0.0, 0.0)).norm(), 0.0, kRoundOff);
    EXPECT_GT(spray.radius[i], 0.0);
  }
  {  // The drops are state: saved and restored with the particles, bit for bit.
    sdk::StateBuffer saved;
    sdk::StateWriter writer(saved);
    particles.save(writer);
    ParticleLevelSet copy({{"per_cell", 8}, {"reseed_every", 10}, {"seed", 0}}, grid, 24.0,
                          gravity);
    sdk::StateReader reader(saved);
    copy.restore(reader);
    EXPECT_EQ(copy.spray().position, spray.position);
    EXPECT_EQ(copy.spray().velocity, spray.velocity);
    EXPECT_EQ(copy.spray().radius, spray.radius);
  }
  const std::vector<double> y0 = spray.position[1], x0 = spray.position[0];
  particles.advect(nodes, dt, none, nullptr);
  // Drops that would pass x = 1 have left the domain; the others keep their order.
  std::int64_t flying = 0;
  for (std::int64_t i = 0; i < expected; ++i) {
    if (x0[i] + 0.5 * dt > 1.0) continue;
    ASSERT_LT(flying, spray.size());
    EXPECT_NEAR(spray.position[0][flying], x0[i] + 0.5 * dt, kRoundOff);
    EXPECT_NEAR(spray.position[1][flying], y0[i] - 0.5 * 9.81 * dt * dt, kRoundOff);
    EXPECT_NEAR(spray.velocity[1][flying], -9.81 * dt, kRoundOff);
    ++flying;
  }
  EXPECT_EQ(spray.size(), flying);
  EXPECT_EQ(particles.stats().landed, expected - flying);
  ASSERT_GT(flying, 100);
  fill_below(level_set, 0.95);  // the water rises over every drop
  particles.adjust(level_set, none);
  EXPECT_EQ(particles.spray().size(), 0);
  EXPECT_EQ(particles.stats().landed, expected);
}

}  // namespace
}  // namespace shellflow::grid_fluid
