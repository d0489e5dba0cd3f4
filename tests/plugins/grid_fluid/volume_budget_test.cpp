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

/// The level set's own budget (water_cells_budget_test has its flows through open sides and
/// emitters).
nlohmann::json tank(nlohmann::json water, nlohmann::json boundary = nlohmann::json::object()) {
  return {{"resolution", 24},
          {"pressure", {{"tolerance", 1e-8}}},
          {"boundary", std::move(boundary)},
          {"water", test::water_core("cells", std::move(water))}};
}

using test::run_for;

TEST(VolumeBudget, AClosedTankLetsNothingOut) {
  auto fluid = test::make_fluid(
      tank({{"initial", {{{"type", "box"}, {"min", {0.0, 0.0, 0.0}}, {"max", {0.3, 0.5, 1.0}}}}}}));
  run_for(*fluid, 0.2);
  EXPECT_EQ(test::reported(*fluid, "water_volume_outflow"), 0.0);
  EXPECT_EQ(test::reported(*fluid, "water_volume_added"), 0.0);
  EXPECT_EQ(test::reported(*fluid, "water_volume_drift"),
            test::reported(*fluid, "water_volume_change"));
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
  EXPECT_NE(warned.front().find("docs/known-limits.md"), std::string::npos);  // why, once
  long last = 0;
  for (const std::string& line : warned) {
    const double percent = std::stod(line.substr(line.find("volume is ") + 10));
    EXPECT_GT(level_of(std::abs(percent) / 100.0), last) << line;
    last = level_of(std::abs(percent) / 100.0);
  }
  EXPECT_EQ(last, level_of(largest));
  for (size_t i = 1; i < warned.size(); ++i)
    EXPECT_EQ(warned[i].find("known-limits.md"), std::string::npos);
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
    EXPECT_GT(emitter_held_flow(liquid.level_set().mac_grid(), liquid.sources()[0], 0.0), 0.0);
  }
}

}  // namespace
}  // namespace shellflow::grid_fluid
