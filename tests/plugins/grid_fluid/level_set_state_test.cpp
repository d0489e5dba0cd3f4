// The water's level set in a saved state (level_set_state.hpp): a cell-centred scene
// restores bit for bit; a state of the other layout, or one saved before the layout was
// recorded, is refused with both layouts named and what to do; such an older state still
// restores into a node scene.

#include "shellflow/grid_fluid/water/level_set_state.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
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

/// `state` as grid_fluid saved it before the layout was recorded: the tag before φ's
/// column cut out. The column is found by its bytes (length, width 1, φ), which occur once.
sdk::StateBuffer without_layout_tag(const sdk::StateBuffer& state, const std::vector<double>& phi) {
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
  std::int64_t tag = 0;
  std::memcpy(&tag, &*(at - 8), 8);
  EXPECT_EQ(tag, -1);  // the nodes' tag
  sdk::StateBuffer old(state.begin(), at - 8);
  old.insert(old.end(), at, state.end());
  return old;
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

TEST(WaterCheckpoint, AStateOfTheOtherLayoutIsRefusedNamingBoth) {
  auto nodes = falling_box("nodes");
  auto cells = falling_box("cells");
  const std::string into_cells = refusal(*cells, saved_state(*nodes));
  const std::string into_nodes = refusal(*nodes, saved_state(*cells));
  for (const std::string& message : {into_cells, into_nodes}) {
    EXPECT_NE(message.find("\"nodes\""), std::string::npos) << message;
    EXPECT_NE(message.find("\"cells\""), std::string::npos) << message;
    EXPECT_NE(message.find("/fluid/water/level_set"), std::string::npos) << message;
    EXPECT_NE(message.find("--overwrite"), std::string::npos) << message;
  }
  // What to set: the saved state's layout.
  EXPECT_NE(into_cells.find("set /fluid/water/level_set to \"nodes\""), std::string::npos)
      << into_cells;
  EXPECT_NE(into_nodes.find("set /fluid/water/level_set to \"cells\""), std::string::npos)
      << into_nodes;
}

TEST(WaterCheckpoint, AStateSavedBeforeTheLayoutWasRecordedRestoresOnNodesOnly) {
  auto fluid = falling_box("nodes");
  for (int s = 0; s < 5; ++s) step(*fluid, 0.01 * s);
  const sdk::StateBuffer state = saved_state(*fluid);
  const sdk::StateBuffer old = without_layout_tag(state, fluid->liquid()->level_set().phi());
  ASSERT_EQ(old.size() + 8, state.size());
  step(*fluid, 0.05);
  const std::vector<double> phi = fluid->liquid()->level_set().phi();
  auto restored = falling_box("nodes");
  sdk::StateReader in(old);
  restored->restore(in);
  EXPECT_TRUE(in.at_end());
  step(*restored, 0.05);
  EXPECT_EQ(restored->liquid()->level_set().phi(), phi);

  auto cells = falling_box("cells");
  const std::string message = refusal(*cells, old);
  EXPECT_NE(message.find("before the layout was recorded"), std::string::npos) << message;
  EXPECT_NE(message.find("set /fluid/water/level_set to \"nodes\""), std::string::npos) << message;
}

}  // namespace
}  // namespace shellflow::grid_fluid
