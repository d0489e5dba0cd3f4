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

TEST(FluidProbes, AProbeThatNeverMeetsTheDomainIsRefusedNamingItsPath) {
  // Each probe lies wholly outside the domain [0, 1]³: validate refuses it at its own
  // path, after a valid probe at /0, with its extent and the domain's. The last segment's
  // bounding box overlaps the domain; the segment passes the edge x = y = 1 at 0.07.
  const nlohmann::json level = {
      {"type", "water_extent"}, {"name", "level"}, {"from", {0.5, 0, 0.5}}, {"to", {0.5, 1, 0.5}}};
  const auto probe = [](nlohmann::json p) {
    p["name"] = "outside";
    return p;
  };
  const std::vector<std::pair<nlohmann::json, std::string>> cases = {
      {probe({{"type", "box"}, {"min", {2, 2, 2}}, {"max", {3, 3, 3}}}),
       "the box probe [(2, 2, 2), (3, 3, 3)] lies entirely outside the domain [(0, 0, 0), "
       "(1, 1, 1)], so it would always read 0"},
      {probe({{"type", "water_extent"}, {"from", {-1, 0.5, 0.5}}, {"to", {-0.5, 0.5, 0.5}}}),
       "the water_extent probe's segment from (-1, 0.5, 0.5) to (-0.5, 0.5, 0.5) lies entirely "
       "outside the domain [(0, 0, 0), (1, 1, 1)], so it would never sample the water in it"},
      {probe({{"type", "water_extent"}, {"from", {1.5, 0.6, 0.5}}, {"to", {0.6, 1.5, 0.5}}}),
       "the water_extent probe's segment from (1.5, 0.6, 0.5) to (0.6, 1.5, 0.5) lies entirely "
       "outside"},
  };
  for (const auto& [outside, message_part] : cases) {
    SCOPED_TRACE(outside.dump());
    const std::string message =
        test::validate_refusal({{"resolution", 8},
                                {"water", {{"initial", {{{"type", "pool"}, {"height", 0.5}}}}}},
                                {"probes", {level, outside}}});
    EXPECT_THAT(message, HasSubstr(std::string(test::kRefusedScene) + ": /fluid/probes/1: "));
    EXPECT_THAT(message, HasSubstr(message_part));
  }
}

TEST(FluidProbes, AProbeOnAFaceOrPartlyOutsideIsAccepted) {
  // A probe reads the nodes on the domain's faces, so a flat box on the face x = 0 counts
  // them (17 x 17 nodes of Δx³ = 1/4096 each, exact in binary) and a segment along the
  // floor's edge is accepted; so is a box partly outside.
  std::unique_ptr<GridFluid> fluid;
  ASSERT_NO_THROW(
      fluid = test::make_fluid(
          {{"resolution", 16},
           {"probes",
            {{{"type", "box"}, {"name", "face"}, {"min", {0, 0, 0}}, {"max", {0, 1, 1}}},
             {{"type", "box"}, {"name", "across"}, {"min", {-1, -1, -1}}, {"max", {0.5, 2, 2}}},
             {{"type", "water_extent"},
              {"name", "edge"},
              {"from", {0, 0, 0}},
              {"to", {1, 0, 0}}}}}}));
  for (auto& d : fluid->nodes().density()) d = 1.0;
  EXPECT_EQ(test::reported(*fluid, "face.smoke_mass"), 17.0 * 17.0 / 4096.0);
  EXPECT_EQ(test::reported(*fluid, "across.smoke_mass"), 9.0 * 17.0 * 17.0 / 4096.0);
}

}  // namespace
}  // namespace shellflow::grid_fluid
