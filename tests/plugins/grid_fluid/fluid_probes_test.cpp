// grid_fluid's probes: the figures they write to metrics.csv on fields whose answer is
// exact (a linear φ, a uniform density), so that bench measures built on them start from a
// known column.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "grid_fluid_test_support.hpp"

namespace shellflow::grid_fluid {
namespace {

using ::testing::HasSubstr;

// A handful of operations on numbers of order one: round-off.
constexpr double kRoundOff = 1e-12;

TEST(FluidProbes, PoolSurfaceHeightAndVolume) {
  // φ = y − 0.41 (a signed distance, clamped far from the surface): trilinear sampling and
  // the linear interpolation of the crossing are exact for it.
  const auto fluid = test::make_fluid(
      {{"resolution", 16},
       {"water", {{"initial", {{{"type", "pool"}, {"height", 0.41}}}}}},
       {"probes",
        {{{"type", "water_extent"},
          {"name", "level"},
          {"from", {0.5, 0, 0.5}},
          {"to", {0.5, 1, 0.5}}},
         {{"type", "water_extent"},
          {"name", "air"},
          {"from", {0.5, 0.7, 0.5}},
          {"to", {0.5, 0.9, 0.5}}},
         {{"type", "box"}, {"name", "all"}, {"min", {0, 0, 0}}, {"max", {1, 1, 1}}},
         {{"type", "box"}, {"name", "top"}, {"min", {0, 0.6, 0}}, {"max", {1, 1, 1}}}}}});
  EXPECT_NEAR(test::reported(*fluid, "level.extent"), 0.41, kRoundOff);
  EXPECT_EQ(test::reported(*fluid, "air.extent"), 0.0);
  // The box over the whole tank sums what LevelSet::volume sums (in another order).
  EXPECT_NEAR(test::reported(*fluid, "all.water_volume"), fluid->liquid()->level_set().volume(),
              kRoundOff);
  EXPECT_EQ(test::reported(*fluid, "top.water_volume"), 0.0);
}

TEST(FluidProbes, DamBreakFrontAlongTheFloor) {
  // A column of water 0.25 m wide against the x = 0 wall: along the floor φ = x − 0.25.
  const auto fluid = test::make_fluid(
      {{"domain", {{"min", {0, 0, 0}}, {"max", {1, 0.625, 0.0625}}}},
       {"resolution", 32},
       {"water",
        {{"initial", {{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.25, 0.5, 1}}}}}}},
       {"probes",
        {{{"type", "water_extent"},
          {"name", "front"},
          {"from", {0, 0, 0.03125}},
          {"to", {1, 0, 0.03125}}}}}});
  EXPECT_NEAR(test::reported(*fluid, "front.extent"), 0.25, kRoundOff);
}

TEST(FluidProbes, SmokeMassInABox) {
  auto fluid = test::make_fluid(
      {{"resolution", 16},
       {"probes",
        {{{"type", "box"}, {"name", "left"}, {"min", {0, 0, 0}}, {"max", {0.5, 1, 1}}}}}});
  for (auto& d : fluid->nodes().density()) d = 1.0;
  // Nodes with x <= 0.5: 9 x 17 x 17 of them, each Δx³ = 1/4096 (exact in binary).
  EXPECT_EQ(test::reported(*fluid, "left.smoke_mass"), 9.0 * 17.0 * 17.0 / 4096.0);
}

TEST(FluidProbes, VelocityErrorAgainstTheInitialField) {
  // The faces start as the Taylor–Green vortex of amplitude 1.1 and the probe's reference
  // is the same vortex at amplitude 1: every face is off by 0.1 of its reference value, so
  // both relative errors are 0.1 (the walls' zero faces are exact in both).
  const nlohmann::json vortex = {{"type", "taylor_green"}, {"amplitude", 1.0}};
  const nlohmann::json probe = {{"type", "velocity_error"}, {"name", "tg"}, {"reference", vortex}};
  const auto off =
      test::make_fluid({{"resolution", 8},
                        {"initial_velocity", {{"type", "taylor_green"}, {"amplitude", 1.1}}},
                        {"probes", {probe}}});
  EXPECT_NEAR(test::reported(*off, "tg.max_error"), 0.1, kRoundOff);
  EXPECT_NEAR(test::reported(*off, "tg.rms_error"), 0.1, kRoundOff);
  // The same field as the reference: no error but round-off (the walls hold exactly 0 where
  // the reference holds sin(π) ≈ 1.2e-16).
  const auto same =
      test::make_fluid({{"resolution", 8}, {"initial_velocity", vortex}, {"probes", {probe}}});
  EXPECT_NEAR(test::reported(*same, "tg.max_error"), 0.0, kRoundOff);
  EXPECT_NEAR(test::reported(*same, "tg.rms_error"), 0.0, kRoundOff);
  // A reference that is zero everywhere gives no scale to an error.
  nlohmann::json still = probe;
  still["reference"]["amplitude"] = 0.0;
  EXPECT_THROW(test::make_fluid({{"probes", {still}}}), ConfigError);
}

TEST(FluidProbes, NamesAreUniqueColumnPrefixes) {
  const auto probe = [](const std::string& name) {
    return nlohmann::json{{"type", "box"}, {"name", name}, {"min", {0, 0, 0}}, {"max", {1, 1, 1}}};
  };
  try {
    test::make_fluid({{"probes", {probe("a"), probe("a")}}});
    FAIL() << "a repeated probe name was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/probes/1/name");
    EXPECT_THAT(e.what(), HasSubstr("used twice"));
  }
  EXPECT_THROW(test::make_fluid({{"probes", {probe("a.b")}}}), ConfigError);
}

}  // namespace
}  // namespace shellflow::grid_fluid
