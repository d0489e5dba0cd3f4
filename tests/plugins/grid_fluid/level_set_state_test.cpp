// The water's level set in a saved state (level_set_state.hpp): a scene restores bit for
// bit; a state of the removed node level set (tagged so, or saved before the tag was
// written) is refused, naming the change and what to do.

#include "shellflow/grid_fluid/water/level_set_state.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

#include "grid_fluid_test_support.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {
namespace {

/// A box of water falling in a 8 x 16 x 8 tank on `core` (test::water_core's).
std::unique_ptr<GridFluid> falling_box(const std::string& core) {
  return test::make_fluid(
      {{"resolution", 16},
       {"domain", {{"min", {0.0, 0.0, 0.0}}, {"max", {0.5, 1.0, 0.5}}}},
       {"water",
        test::water_core(core, {{"initial", {{{"type", "box"},
                                              {"min", {0.15, 0.4, 0.15}},
                                              {"max", {0.35, 0.6, 0.35}}}}}})}});
}

void step(GridFluid& fluid, double t) {
  fluid.advect(t, 0.01, {}, {});
  fluid.project(0.01, {}, {});
}

sdk::StateBuffer saved_state(const GridFluid& fluid) {
  sdk::StateBuffer state;
  sdk::StateWriter out(state);
  fluid.save(out);
  return state;
}

/// The message restore() throws, empty (and a test failure) when it restores.
std::string refusal(GridFluid& fluid, const sdk::StateBuffer& state) {
  try {
    sdk::StateReader in(state);
    fluid.restore(in);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "the state was restored";
  return {};
}

/// `state` with the tag before φ's column replaced by `tag`, or cut out (nullopt: a state
/// saved before the tag was written, all of them on the nodes). The column is found by its
/// bytes (length, width 1, φ), which occur once.
sdk::StateBuffer retagged(const sdk::StateBuffer& state, const std::vector<double>& phi,
                          std::optional<std::int64_t> tag) {
  std::vector<std::uint8_t> column(16 + 8 * phi.size());
  const std::int64_t header[2] = {static_cast<std::int64_t>(phi.size()), 1};
  std::memcpy(column.data(), header, 16);
  std::memcpy(column.data() + 16, phi.data(), 8 * phi.size());
  const auto at = std::search(state.begin(), state.end(), column.begin(), column.end());
  if (at == state.end() || at - state.begin() < 8) {
    ADD_FAILURE() << "φ's column is not in the state";
    return {};
  }
  EXPECT_EQ(std::search(at + 1, state.end(), column.begin(), column.end()), state.end());
  std::int64_t saved_tag = 0;
  std::memcpy(&saved_tag, &*(at - 8), 8);
  EXPECT_EQ(saved_tag, -2);  // the cell centres' tag
  sdk::StateBuffer out(state.begin(), at - 8);
  if (tag) {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(&*tag);
    out.insert(out.end(), bytes, bytes + 8);
  }
  out.insert(out.end(), at, state.end());
  return out;
}

TEST(WaterCheckpoint, ACellCentredSceneRestoresBitForBit) {
  // The coupling loop rewinds and a resumed run continues from a checkpoint (§4.3, §6): a
  // step from the restored state repeats the step from the saved one exactly.
  auto fluid = falling_box("cells");
  for (int s = 0; s < 5; ++s) step(*fluid, 0.01 * s);
  const sdk::StateBuffer state = saved_state(*fluid);
  step(*fluid, 0.05);
  const std::vector<double> phi = fluid->liquid()->level_set().phi();
  const auto v = fluid->mac().face_velocity(1);
  const double volume = fluid->liquid()->volume(nullptr, nullptr);
  // Not vacuous: the step changed φ.
  auto other = falling_box("cells");
  ASSERT_NE(phi, other->liquid()->level_set().phi());
  sdk::StateReader in(state);
  other->restore(in);
  EXPECT_TRUE(in.at_end());
  step(*other, 0.05);
  EXPECT_EQ(other->liquid()->level_set().phi(), phi);
  EXPECT_EQ(other->mac().face_velocity(1), v);
  EXPECT_EQ(other->liquid()->volume(nullptr, nullptr), volume);
}

TEST(WaterCheckpoint, AVolumeFractionSceneRestoresBitForBit) {
  // F, the faces it moves with next and its sweeps' order are state too: a step from the
  // restored state repeats the saved one's exactly, through the landing (0.29 s). An odd
  // number of steps first, so that the sweeps' order differs from a fresh fluid's.
  auto fluid = falling_box("fraction");
  for (int s = 0; s < 29; ++s) step(*fluid, 0.01 * s);
  const sdk::StateBuffer state = saved_state(*fluid);
  step(*fluid, 0.29);
  const std::vector<double> fraction = fluid->liquid()->fraction().values();
  const std::vector<double> phi = fluid->liquid()->level_set().phi();
  auto other = falling_box("fraction");
  ASSERT_NE(fraction, other->liquid()->fraction().values());  // not vacuous
  sdk::StateReader in(state);
  other->restore(in);
  EXPECT_TRUE(in.at_end());
  step(*other, 0.29);
  EXPECT_EQ(other->liquid()->fraction().values(), fraction);
  EXPECT_EQ(other->liquid()->level_set().phi(), phi);
  // A state saved without the fraction cannot give one back, nor one with it be read by a
  // scene without.
  auto without = falling_box("cells");
  const std::string message = refusal(*other, saved_state(*without));
  EXPECT_NE(message.find("/fluid/water/volume_fraction"), std::string::npos) << message;
  const std::string other_way = refusal(*without, saved_state(*other));
  EXPECT_NE(other_way.find("volume_fraction"), std::string::npos) << other_way;
}

TEST(WaterCheckpoint, AVolumeFractionAmongShellsRestoresBitForBit) {
  // The box lands on a shelf across the tank: the cells the shelf cuts are found from the
  // shells each step (no state), so a restored run repeats the saved one's step exactly.
  const std::vector<sdk::ShellSurface> shelf{
      test::make_plate({0.25, 0.27, 0.25}, Eigen::Vector3d::UnitY(), 0.7, 7)};
  const std::vector<sdk::Positions> v_eff{shelf.front().velocities};
  const auto shelf_step = [&](GridFluid& f, double t) {
    f.advect(t, 0.01, shelf, shelf);
    f.project(0.01, shelf, v_eff);
  };
  auto fluid = falling_box("fraction");
  for (int s = 0; s < 29; ++s) shelf_step(*fluid, 0.01 * s);
  const sdk::StateBuffer state = saved_state(*fluid);
  shelf_step(*fluid, 0.29);
  const std::vector<double> fraction = fluid->liquid()->fraction().values();
  auto other = falling_box("fraction");
  sdk::StateReader in(state);
  other->restore(in);
  shelf_step(*other, 0.29);
  EXPECT_EQ(other->liquid()->fraction().values(), fraction);
  EXPECT_EQ(other->liquid()->level_set().phi(), fluid->liquid()->level_set().phi());
  EXPECT_EQ(other->mac().face_velocity(1), fluid->mac().face_velocity(1));
}

TEST(WaterCheckpoint, AStateOfTheRemovedNodeLevelSetIsRefusedNamingTheChange) {
  // φ on the grid's nodes, tagged −1, or untagged from before the tag was written: its
  // samples mean other points, so it cannot be continued.
  auto fluid = falling_box("cells");
  const sdk::StateBuffer state = saved_state(*fluid);
  const std::vector<double>& phi = fluid->liquid()->level_set().phi();
  for (const std::optional<std::int64_t> tag :
       {std::optional<std::int64_t>(-1), std::optional<std::int64_t>()}) {
    const sdk::StateBuffer old = retagged(state, phi, tag);
    ASSERT_EQ(old.size() + (tag ? 0 : 8), state.size());
    const std::string message = refusal(*fluid, old);
    EXPECT_NE(message.find("on the grid's nodes"), std::string::npos) << message;
    EXPECT_NE(message.find("cell centres"), std::string::npos) << message;
    EXPECT_NE(message.find("--overwrite"), std::string::npos) << message;
  }
  const std::string unknown = refusal(*fluid, retagged(state, phi, -7));
  EXPECT_NE(unknown.find("unknown tag -7"), std::string::npos) << unknown;
  sdk::StateReader in(state);  // and the state as saved restores
  EXPECT_NO_THROW(fluid->restore(in));
}

}  // namespace
}  // namespace shellflow::grid_fluid
