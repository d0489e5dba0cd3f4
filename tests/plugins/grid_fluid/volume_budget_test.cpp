// The water's volume budget (VolumeBudget): what the emitters add and the open sides let
// out, so that water_volume_drift = V − V(0) − added + outflow measures the solver's own
// error in scenes whose water is not meant to stay what it was; an emitter that
// could add no water (wholly outside the domain) is refused by name.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "../logged_messages.hpp"
#include "grid_fluid_test_support.hpp"
#include "shellflow/grid_fluid/water/volume_budget.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::grid_fluid {
namespace {

/// The area of {(x, y) in the unit square : p + q x + r y < 0}, r != 0: the wet length of
/// each column x, integrated by the midpoint rule (piecewise linear in x: error O(h^2)
/// only at its two kinks, 1e-12 with 10^6 columns).
double wet_area(double p, double q, double r) {
  const int columns = 1000000;
  double area = 0.0;
  for (int i = 0; i < columns; ++i) {
    const double x = (i + 0.5) / columns;
    const double y0 = -(p + q * x) / r;  // where the line crosses the column
    area += r > 0.0 ? std::clamp(y0, 0.0, 1.0) : 1.0 - std::clamp(y0, 0.0, 1.0);
  }
  return area / columns;
}

TEST(VolumeBudget, AFaceWetFractionIsExactForALinearLevelSet) {
  // φ = p + q x + r y is linear on each of the face's triangles, so the fraction is exact
  // (to round-off) for every line, whichever diagonal the face is cut along.
  const double cases[][3] = {{-0.3, 1.0, 0.0001}, {0.2, -1.0, -0.5}, {-0.5, 1.0, 1.0},
                             {-1.2, 1.0, 1.0},    {0.3, -0.4, 1.0},  {-0.1, 0.7, -0.9},
                             {-0.25, 0.5, 0.25},  {5.0, 1.0, 1.0},   {-5.0, 1.0, 1.0}};
  for (const auto& c : cases) {
    const auto phi = [&](double x, double y) { return c[0] + c[1] * x + c[2] * y; };
    const std::array<double, 4> corner = {phi(0, 0), phi(1, 0), phi(0, 1), phi(1, 1)};
    EXPECT_NEAR(face_water_fraction(corner), wet_area(c[0], c[1], c[2]), 1e-9)
        << "phi = " << c[0] << " + " << c[1] << " x + " << c[2] << " y";
  }
}

/// The node core's budget (water_cells_budget_test has the cells').
nlohmann::json tank(nlohmann::json water, nlohmann::json boundary = nlohmann::json::object()) {
  return {{"resolution", 24},
          {"pressure", {{"tolerance", 1e-8}}},
          {"boundary", std::move(boundary)},
          {"water", test::water_core("nodes", std::move(water))}};
}

using test::run_for;

TEST(VolumeBudget, WaterFallingThroughAnOpenFloorIsCountedOut) {
  // A slab of water 0.2 m deep across a unit tank falls freely through its open floor
  // (its bottom at 0.3 m: out from t = 0.25 s, the top from 0.32 s). Its φ is linear
  // through each surface, which the level set moves exactly, so what leaves is what the
  // tank loses, to round-off, part way (a surface within a step of the floor) and once
  // the slab has gone. Counted as a rate at either end of each step, it came out 8% short.
  auto fluid = test::make_fluid(
      tank({{"initial", {{{"type", "box"}, {"min", {-1.0, 0.3, -1.0}}, {"max", {2.0, 0.5, 2.0}}}}}},
           {{"y_min", {{"type", "open"}}}}));
  const double v0 = fluid->liquid()->level_set().volume();
  run_for(*fluid, 0.28);
  const double partway = test::reported(*fluid, "water_volume_outflow");
  const double lost = v0 - test::reported(*fluid, "water_volume");
  run_for(*fluid, 0.17);
  const double out = test::reported(*fluid, "water_volume_outflow");
  const double left = test::reported(*fluid, "water_volume");
  const double drift = test::reported(*fluid, "water_volume_drift");
  std::printf(
      "[  figure  ] slab through an open floor: V0 %.6f, out %.9f (%.9f of %.9f lost "
      "at 0.28 s), left %.2e\n",
      v0, out, partway, lost, left);
  EXPECT_GT(partway, 0.1 * v0);  // part of it had left, not all
  EXPECT_LT(partway, 0.9 * v0);
  EXPECT_NEAR(partway, lost, 1e-9 * v0);
  EXPECT_EQ(left, 0.0);
  EXPECT_NEAR(out, v0, 1e-9 * v0);
  EXPECT_NEAR(drift, left - v0 + out, 1e-15);
}

TEST(VolumeBudget, AClosedTankLetsNothingOut) {
  auto fluid = test::make_fluid(
      tank({{"initial", {{{"type", "box"}, {"min", {0.0, 0.0, 0.0}}, {"max", {0.3, 0.5, 1.0}}}}}}));
  run_for(*fluid, 0.2);
  EXPECT_EQ(test::reported(*fluid, "water_volume_outflow"), 0.0);
  EXPECT_EQ(test::reported(*fluid, "water_volume_added"), 0.0);
  EXPECT_EQ(test::reported(*fluid, "water_volume_drift"),
            test::reported(*fluid, "water_volume_change"));
}

TEST(VolumeBudget, AnEmitterAddsWhatItsHeldFacesLetOut) {
  // An emitter across the whole tank (3 cells deep, its velocity 1 m/s down) under a
  // column of air: its held faces move the water below it at 1 m/s as one (the walls
  // leave it no other way), so it fills its own cells in the first step and from the next
  // on adds 1 m/s over the tank's 1 m², to round-off; the column's flat front keeps the
  // volume (the level set moves a linear φ exactly).
  const double dx = 1.0 / 24;
  auto fluid = test::make_fluid(tank({{"sources",
                                       {{{"shape", "box"},
                                         {"min", {-1.0, 0.75, -1.0}},
                                         {"max", {2.0, 0.875, 2.0}},
                                         {"velocity", {0.0, -1.0, 0.0}}}}}}));
  const double content = 3 * dx;  // 24 x 24 x 3 cells
  run_for(*fluid, 0.01);
  EXPECT_NEAR(test::reported(*fluid, "water_volume_added"), content, 1e-12);
  const double flowing = 0.29;  // after the first step
  run_for(*fluid, flowing);
  const double added = test::reported(*fluid, "water_volume_added");
  const double drift = test::reported(*fluid, "water_volume_drift");
  std::printf("[  figure  ] full-width emitter: added %.9f against %.9f, drift %.2e\n", added,
              content + flowing, drift);
  EXPECT_NEAR(added, content + flowing, 1e-9);
  EXPECT_LT(std::abs(drift), 1e-6 * added);
}

TEST(VolumeBudget, ACylinderEmitterLetsOutWhatItsHeldFacesImpose) {
  // A cylinder emitter 0.2 m in radius (4.8 cells at 24), 1 m/s down, on for 0.2 s: after
  // its first step's fill, it adds 1 m/s over the faces under its cells (those whose
  // centre lies within the radius), exactly: the flow its held faces impose on the
  // divergence-free velocity (+5% on π r² v at this radius). What the level set then
  // makes of it (the stream speeding up and thinning, apply() topping the rim up) is drift.
  auto fluid = test::make_fluid(tank({{"sources",
                                       {{{"shape", "cylinder"},
                                         {"from", {0.5, 0.8, 0.5}},
                                         {"to", {0.5, 0.9, 0.5}},
                                         {"radius", 0.2},
                                         {"velocity", {0.0, -1.0, 0.0}}}}}}));
  const Liquid& liquid = *fluid->liquid();
  const double dx = 1.0 / 24;
  int faces = 0;
  for (int k = 0; k < 24; ++k)
    for (int i = 0; i < 24; ++i)
      faces += std::hypot((i + 0.5) * dx - 0.5, (k + 0.5) * dx - 0.5) <= 0.2 ? 1 : 0;
  const double flow = emitter_held_flow(liquid.level_set().grid(), liquid.sources()[0], 0.0);
  EXPECT_NEAR(flow, faces * dx * dx, 1e-12);
  run_for(*fluid, 0.01);  // filled
  const double filled = test::reported(*fluid, "water_volume_added");
  const double flowing = 0.19;
  run_for(*fluid, flowing);
  const double added = test::reported(*fluid, "water_volume_added");
  std::printf(
      "[  figure  ] cylinder emitter: %d faces, %.5f m^3/s against pi r^2 v = %.5f; "
      "filled %.6f, then %.6f in %.2f s, drift %+.2f%%\n",
      faces, flow, std::numbers::pi * 0.04, filled, added - filled, flowing,
      100.0 * test::reported(*fluid, "water_volume_drift") / added);
  EXPECT_NEAR(added - filled, flow * flowing, 1e-12);
  EXPECT_GT(filled, 0.9 * std::numbers::pi * 0.04 * 0.1);  // the cylinder, filled
}

TEST(VolumeBudget, SaveAndRestoreCarryTheBudget) {
  // The coupling loop rewinds and a run resumes from its checkpoint: a step from the
  // restored state must count what the step from the saved one counted, bit for bit. A
  // stream from a box emitter falling through an open floor, saved at 0.45 s, with the
  // phases' sums on.
  auto fluid = test::make_fluid(tank({{"volume_by_phase", true},
                                      {"sources",
                                       {{{"shape", "box"},
                                         {"min", {0.4, 0.8, 0.4}},
                                         {"max", {0.6, 0.9, 0.6}},
                                         {"velocity", {0.0, -1.0, 0.0}}}}}},
                                     {{"y_min", {{"type", "open"}}}}));
  run_for(*fluid, 0.45);  // the stream reaches the floor at 0.32 s
  sdk::StateBuffer saved;
  sdk::StateWriter writer(saved);
  fluid->save(writer);
  const auto step = [&] {
    fluid->advect(0.45, 0.01, {}, {});
    fluid->project(0.01, {}, {});
    return std::array{test::reported(*fluid, "water_volume_added"),
                      test::reported(*fluid, "water_volume_outflow"),
                      test::reported(*fluid, "water_volume_drift"),
                      test::reported(*fluid, "water_drift_advection"),
                      test::reported(*fluid, "water_drift_between_steps")};
  };
  const auto first = step();
  EXPECT_GT(first[0], 0.0);
  EXPECT_GT(first[1], 0.0);  // the stream has reached the floor
  sdk::StateReader reader(saved);
  fluid->restore(reader);
  EXPECT_EQ(step(), first);
}

TEST(VolumeBudget, ThePhasesDriftsAddUpToTheDrift) {
  // "volume_by_phase": the water measured between the phases of each step. Without shells
  // the measure does not depend on the step's band, so the phases' sums add up to
  // water_volume_drift to round-off; a collapsing column, a stream and an open floor make
  // every phase move water; a prescribed velocity's advection counts as advection. Off,
  // none is written.
  auto water = nlohmann::json{
      {"volume_by_phase", true},
      {"initial", {{{"type", "box"}, {"min", {0.0, 0.0, 0.0}}, {"max", {0.3, 0.5, 1.0}}}}},
      {"sources",
       {{{"shape", "cylinder"},
         {"from", {0.7, 0.8, 0.5}},
         {"to", {0.7, 0.9, 0.5}},
         {"radius", 0.1},
         {"velocity", {0.0, -1.0, 0.0}}}}}};
  auto fluid = test::make_fluid(tank(water, {{"x_max", {{"type", "open"}}}}));
  run_for(*fluid, 0.4);
  const double advection = test::reported(*fluid, "water_drift_advection");
  const double reinitialization = test::reported(*fluid, "water_drift_reinitialization");
  const double sum = advection + test::reported(*fluid, "water_drift_shells") + reinitialization +
                     test::reported(*fluid, "water_drift_between_steps");
  const double drift = test::reported(*fluid, "water_volume_drift");
  std::printf(
      "[  figure  ] drift by phase: advection %+.3e, reinitialisation %+.3e, sum %+.6e "
      "against %+.6e\n",
      advection, reinitialization, sum, drift);
  EXPECT_NE(advection, 0.0);
  EXPECT_NE(reinitialization, 0.0);
  EXPECT_NEAR(sum, drift, 1e-12);
  // A prescribed velocity (no emitters, no projection): its advection is advection's too.
  auto carried = test::make_fluid(
      {{"resolution", 16},
       {"water",
        test::water_core(
            "nodes", {{"volume_by_phase", true},
                      {"initial",
                       {{{"type", "sphere"}, {"center", {0.35, 0.35, 0.35}}, {"radius", 0.15}}}}})},
       {"prescribed_velocity", {{"type", "deformation"}, {"period", 3.0}}}},
      Eigen::Vector3d::Zero());
  run_for(*carried, 0.3);
  EXPECT_NE(test::reported(*carried, "water_drift_advection"), 0.0);
  EXPECT_EQ(test::reported(*carried, "water_drift_shells"), 0.0);
  EXPECT_NEAR(test::reported(*carried, "water_drift_advection") +
                  test::reported(*carried, "water_drift_reinitialization") +
                  test::reported(*carried, "water_drift_between_steps"),
              test::reported(*carried, "water_volume_drift"), 1e-12);
  water["volume_by_phase"] = false;
  auto off = test::make_fluid(tank(water));
  sdk::Metrics m;
  off->report(m);
  for (const auto& [key, value] : m.values())
    EXPECT_EQ(key.find("water_drift_"), std::string::npos);
}

/// The drift warnings among `log`'s lines.
std::vector<std::string> drift_warnings(const testing::LoggedMessages& log) {
  std::vector<std::string> out;
  for (const std::string& line : log.lines())
    if (line.find("volume is") != std::string::npos) out.push_back(line);
  return out;
}

/// Steps `fluid` for `duration` as the runtime does, reporting after each step; returns
/// the largest |water_volume_drift| / (V0 + added − outflow) it reported.
double run_reporting(GridFluid& fluid, double duration) {
  double t = 0.0, largest = 0.0;
  const double v0 = test::reported(fluid, "water_volume");
  while (t < duration - 1e-12) {
    const double dt = std::min(fluid.stable_dt(0.9), duration - t);
    fluid.advect(t, dt, {}, {});
    fluid.project(dt, {}, {});
    t += dt;
    sdk::Metrics m;
    fluid.report(m);
    std::map<std::string, double> r(m.values().begin(), m.values().end());
    const double held = v0 + r["water_volume_added"] - r["water_volume_outflow"];
    largest = std::max(largest, std::abs(r["water_volume_drift"]) / held);
  }
  return largest;
}

TEST(VolumeBudget, LostWaterIsWarnedOfAsItPassesEachLevel) {
  // A drop of water 0.9 of a cell in radius falling in a tank: the level set smooths a feature
  // that small away within a few steps (the known loss of a level set alone), and the log,
  // which a user watches, says so as the loss passes 5, 25, 50 and 90 % of the water.
  const testing::LoggedMessages log(spdlog::level::warn);
  const double dx = 1.0 / 16;
  auto fluid = test::make_fluid(
      {{"resolution", 16},
       {"water",  // the level set alone, which loses such a drop
        test::water_core(
            "cells",
            {{"initial",
              {{{"type", "sphere"}, {"center", {0.5, 0.6, 0.5}}, {"radius", 0.9 * dx}}}}})}});
  const double largest = run_reporting(*fluid, 0.6);
  const std::vector<std::string> warned = drift_warnings(log);
  std::printf("[  figure  ] a drop 0.9 of a cell in radius: largest drift %.1f %%, %zu warnings\n",
              100.0 * largest, warned.size());
  ASSERT_GE(largest, 0.05) << "the drop did not lose enough to test the warning";
  // Each warning names a larger drift than the one before and a level not named yet (a
  // step passing two levels warns once); the last names the level the largest drift passed.
  const std::array<double, 4> levels = {0.05, 0.25, 0.5, 0.9};
  const auto level_of = [&](double d) {
    return std::count_if(levels.begin(), levels.end(), [&](double l) { return d >= l; });
  };
  ASSERT_FALSE(warned.empty());
  EXPECT_NE(warned.front().find("Known limits"), std::string::npos);  // why, once
  long last = 0;
  for (const std::string& line : warned) {
    const double percent = std::stod(line.substr(line.find("volume is ") + 10));
    EXPECT_GT(level_of(std::abs(percent) / 100.0), last) << line;
    last = level_of(std::abs(percent) / 100.0);
  }
  EXPECT_EQ(last, level_of(largest));
  for (size_t i = 1; i < warned.size(); ++i)
    EXPECT_EQ(warned[i].find("Known limits"), std::string::npos);
}

TEST(VolumeBudget, AStillPoolIsNotWarnedOf) {
  // Water at rest keeps its volume to the pressure solve's tolerance: nothing to warn of.
  const testing::LoggedMessages log(spdlog::level::warn);
  auto fluid = test::make_fluid(tank(
      {{"initial", {{{"type", "box"}, {"min", {-1.0, -1.0, -1.0}}, {"max", {2.0, 0.4, 2.0}}}}}}));
  const double largest = run_reporting(*fluid, 0.2);
  EXPECT_LT(largest, 1e-6);
  EXPECT_TRUE(drift_warnings(log).empty());
}

using ::testing::HasSubstr;

TEST(WaterSource, AnEmitterThatAddsNoWaterIsRefusedNamingItsPath) {
  // Each emitter lies wholly outside the domain [0, 1]³ or only touches a face, so it
  // would never add water: validate refuses it at its own path, after a valid emitter at
  // /0, with its extent and the domain's.
  const nlohmann::json inside = {{"shape", "box"},
                                 {"min", {0.4, 0.8, 0.4}},
                                 {"max", {0.6, 0.9, 0.6}},
                                 {"velocity", {0, -1, 0}}};
  const std::vector<std::pair<nlohmann::json, std::string>> cases = {
      {{{"shape", "sphere"}, {"center", {0.5, 1.5, 0.5}}, {"radius", 0.3}},
       "the sphere emitter (bounds [(0.2, 1.2, 0.2), (0.8, 1.8, 0.8)])"},
      // On the face x = 1: no volume shared.
      {{{"shape", "box"}, {"min", {1, 0, 0}}, {"max", {2, 1, 1}}},
       "the box emitter (bounds [(1, 0, 0), (2, 1, 1)])"},
      {{{"shape", "cylinder"}, {"from", {0.5, 0.5, 2}}, {"to", {0.5, 0.5, 3}}, {"radius", 0.2}},
       "the cylinder emitter (bounds [(0.3, 0.3, 1.8), (0.7, 0.7, 3.2)])"},
  };
  for (const auto& [source, shape] : cases) {
    SCOPED_TRACE(source.dump());
    const std::string message =
        test::validate_refusal({{"resolution", 8}, {"water", {{"sources", {inside, source}}}}});
    EXPECT_THAT(message,
                HasSubstr(std::string(test::kRefusedScene) + ": /fluid/water/sources/1: "));
    EXPECT_THAT(message,
                HasSubstr(shape + " lies entirely outside the domain [(0, 0, 0), (1, 1, 1)], "
                                  "so it would never add water"));
  }
}

TEST(WaterSource, AnEmitterPartlyOutsideTheDomainIsAcceptedAndLetsWaterIn) {
  // A nozzle through the lid (fed from outside) and a ball centred on a face are inside in
  // part: accepted, and their held faces let water into the domain.
  const std::vector<nlohmann::json> sources = {
      {{"shape", "box"},
       {"min", {0.4, 0.8, 0.4}},
       {"max", {0.6, 1.2, 0.6}},
       {"velocity", {0, -1, 0}}},
      {{"shape", "sphere"}, {"center", {0, 0.5, 0.5}}, {"radius", 0.3}, {"velocity", {1, 0, 0}}},
  };
  for (const auto& source : sources) {
    SCOPED_TRACE(source.dump());
    std::unique_ptr<GridFluid> fluid;
    ASSERT_NO_THROW(fluid =
                        test::make_fluid({{"resolution", 8}, {"water", {{"sources", {source}}}}}));
    const Liquid& liquid = *fluid->liquid();
    EXPECT_GT(emitter_held_flow(liquid.level_set().grid(), liquid.sources()[0], 0.0), 0.0);
  }
}

}  // namespace
}  // namespace shellflow::grid_fluid
