// The kinematic_shell solid: exact state at t + dt, save/restore bit for bit, config
// errors with their JSON paths, and the plugin's entry point.
#include "shellflow/kinematic_shell/kinematic_shell.hpp"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "shellflow/kinematic_shell/keyframe_motion.hpp"
#include "shellflow/sdk/plugin.hpp"
#include "test_paths.hpp"

namespace shellflow::kinematic_shell {
namespace {

using Json = nlohmann::json;

// See kinematic_motion_test.cpp: positions of O(1) m, a few products each.
constexpr double kRoundOff = 1e-12;

Json keyframe_params() {
  return Json::parse(R"({
    "mesh": {"type": "grid", "width": 2, "height": 1, "nodes_u": 5, "nodes_v": 3},
    "transform": {"translate": [0, 1, 0]},
    "surface_density": 0.5,
    "motion": {"type": "keyframes", "interpolation": "slerp", "keys": [
      {"time": 0, "translate": [0, 0, 0]},
      {"time": 1, "translate": [1, 0, 0], "rotate_axis": [0, 0, 1], "rotate_deg": 90},
      {"time": 2.5, "translate": [1, 2, 0], "rotate_axis": [1, 0, 0], "rotate_deg": 45}]}
  })");
}

sdk::Context context(const std::string& name = "solids/lid") {
  sdk::Context c;
  c.instance_name = name;
  return c;
}

bool bitwise_equal(const sdk::Positions& a, const sdk::Positions& b) {
  return a.rows() == b.rows() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

TEST(KinematicShell, ExposesOneOneWaySurfaceNamedAfterTheInstance) {
  const KinematicShell shell(keyframe_params(), context());
  ASSERT_EQ(shell.surfaces().size(), 1u);
  const auto& s = shell.surfaces()[0];
  EXPECT_EQ(s.name, "solids/lid");
  EXPECT_FALSE(s.receives_fluid_forces);
  EXPECT_EQ(s.node_count(), 15);
  EXPECT_EQ(s.triangle_count(), 2 * 4 * 2);
  EXPECT_EQ(s.surface_density.size(), s.triangle_count());
  EXPECT_EQ(s.surface_density.maxCoeff(), 0.5);
  EXPECT_EQ(s.velocities.rows(), 15);
  // At t = 0 (first key: identity pose) the nodes sit where "transform" put them.
  EXPECT_EQ(s.positions, shell.rest_positions());
  EXPECT_DOUBLE_EQ(shell.rest_positions().col(1).mean(), 1.0);
}

TEST(KinematicShell, AdvanceSetsTheExactScriptedStateAndIgnoresForces) {
  KinematicShell shell(keyframe_params(), context());
  const auto keys = make_motion(keyframe_params().at("motion"));
  sdk::TriangleVectors huge = sdk::TriangleVectors::Constant(16, 3, 1e9);
  double t = 0.0;
  for (const double dt : {0.1, 0.37, 0.02, 1.3, 0.9}) {
    shell.advance(t, dt, std::span<const sdk::TriangleVectors>(&huge, 1));
    t += dt;
    sdk::Positions x, v;
    keys->evaluate(t, shell.rest_positions(), x, v);
    EXPECT_TRUE(bitwise_equal(shell.surfaces()[0].positions, x)) << "t = " << t;
    EXPECT_TRUE(bitwise_equal(shell.surfaces()[0].velocities, v)) << "t = " << t;
    EXPECT_EQ(shell.time(), t);
  }
  // Past the last key (t = 2.72 s) the shell holds still.
  EXPECT_EQ(shell.surfaces()[0].velocities.norm(), 0.0);
}

TEST(KinematicShell, SaveRestoreRoundTripsBitForBit) {
  KinematicShell shell(keyframe_params(), context());
  shell.advance(0.0, 0.3, {});
  sdk::StateBuffer saved;
  sdk::StateWriter writer(saved);
  shell.save(writer);
  const sdk::Positions x_saved = shell.surfaces()[0].positions;

  shell.advance(0.3, 0.1 / 3.0, {});
  const sdk::Positions x_first = shell.surfaces()[0].positions;
  const sdk::Positions v_first = shell.surfaces()[0].velocities;
  shell.advance(0.3 + 0.1 / 3.0, 0.7, {});

  sdk::StateReader reader(saved);
  shell.restore(reader);
  EXPECT_TRUE(reader.at_end());
  EXPECT_TRUE(bitwise_equal(shell.surfaces()[0].positions, x_saved));
  EXPECT_EQ(shell.time(), 0.3);
  shell.advance(0.3, 0.1 / 3.0, {});
  EXPECT_TRUE(bitwise_equal(shell.surfaces()[0].positions, x_first));
  EXPECT_TRUE(bitwise_equal(shell.surfaces()[0].velocities, v_first));

  // A buffer from a shell of another size is refused, not misread.
  Json other = keyframe_params();
  other["mesh"]["nodes_u"] = 6;
  KinematicShell bigger(other, context());
  sdk::StateBuffer wrong;
  sdk::StateWriter w(wrong);
  bigger.save(w);
  sdk::StateReader r(wrong);
  EXPECT_THROW(shell.restore(r), Error);
}

TEST(KinematicShell, StaticByDefaultAndAnalyticEnergy) {
  Json params = {{"mesh", {{"type", "grid"}, {"width", 2.0}, {"height", 3.0}}}};
  KinematicShell still(params, context());
  still.advance(0, 5, {});
  EXPECT_EQ(still.surfaces()[0].positions, still.rest_positions());
  sdk::Metrics m;
  still.report(m);
  ASSERT_EQ(m.values().size(), 5u);  // kinetic energy, centre x/y/z, edge strain
  EXPECT_EQ(m.values()[0].second, 0.0);
  EXPECT_EQ(m.values()[4].first, "max_edge_strain");
  EXPECT_EQ(m.values()[4].second, 0.0);

  params["surface_density"] = 2.0;
  params["motion"] = {{"type", "analytic"}, {"velocity", {3.0, 0.0, 4.0}}};
  KinematicShell moving(params, context());
  moving.advance(0, 0.25, {});
  m.clear();
  moving.report(m);
  // ½ M |v|² with M = 2 kg/m² · 6 m² = 12 kg, |v| = 5 m/s: 150 J (lumped masses sum to M).
  EXPECT_NEAR(m.values()[0].second, 150.0, 150.0 * kRoundOff);
  // The grid is centred at the origin; after 0.25 s at v it is centred at v/4.
  const Eigen::RowVector3d centroid = moving.surfaces()[0].positions.colwise().mean();
  EXPECT_LT((centroid - Eigen::RowVector3d(0.75, 0, 1)).norm(), kRoundOff);
  // The reported centre is that mean of the nodes.
  EXPECT_EQ(m.values()[1].first, "center_x");
  EXPECT_NEAR(m.values()[1].second, 0.75, kRoundOff);
  EXPECT_NEAR(m.values()[2].second, 0.0, kRoundOff);
  EXPECT_NEAR(m.values()[3].second, 1.0, kRoundOff);
}

TEST(KinematicShell, EdgeStrainIsRoundOffForRigidKeysAndTheShearOfLinearOnes) {
  // Slerp keys move the grid rigidly: every edge keeps its length to round-off.
  Json params = keyframe_params();
  KinematicShell rigid(params, context());
  double strain = 0.0;
  sdk::Metrics m;
  for (int n = 0; n < 30; ++n) {
    rigid.advance(n / 12.0, 1.0 / 12.0, {});
    m.clear();
    rigid.report(m);
    strain = std::max(strain, m.values()[4].second);
  }
  EXPECT_LT(strain, kRoundOff);
  // Linear keys move each node on a straight line: a quarter turn about z halfway through is
  // a shear. Halfway, the grid's 0.5 m edge along x (nodes (0, 0) → (1, 0): d = (0.5, 0)) runs
  // from d to R d = (0, 0.5) and is (d + R d)/2 = (0.25, 0.25): 0.3536 m, strain 1 − 1/√2.
  params["motion"]["interpolation"] = "linear";
  KinematicShell shear(params, context());
  shear.advance(0.0, 0.5, {});
  m.clear();
  shear.report(m);
  EXPECT_NEAR(m.values()[4].second, 1.0 - std::sqrt(0.5), kRoundOff);
}

TEST(KinematicShell, BadKeysAreConfigErrorsNamingTheirPath) {
  auto expect_path = [](Json params, const std::string& path) {
    try {
      KinematicShell shell(params, context());
      ADD_FAILURE() << "expected ConfigError at " << path;
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.json_path(), path) << e.what();
    }
  };
  Json unordered = keyframe_params();
  unordered["motion"]["keys"][2]["time"] = 1.0;  // equal to the previous key
  expect_path(unordered, "/motion/keys/2/time");
  Json backwards = keyframe_params();
  backwards["motion"]["keys"][1]["time"] = -1.0;
  expect_path(backwards, "/motion/keys/1/time");
  Json zero_axis = keyframe_params();
  zero_axis["motion"]["keys"][1]["rotate_axis"] = {0, 0, 0};
  expect_path(zero_axis, "/motion/keys/1/rotate_axis");
  Json one_key = keyframe_params();
  one_key["motion"]["keys"].erase(1);
  one_key["motion"]["keys"].erase(1);
  expect_path(one_key, "/motion/keys");
  Json wave = keyframe_params();
  wave["motion"] = {{"type", "wave"}, {"direction", {0, 0, 0}}};
  expect_path(wave, "/motion/direction");
  Json bad_box = keyframe_params();
  bad_box["mesh"] = {{"type", "box"}, {"size", {1, 0, 1}}};
  expect_path(bad_box, "/mesh/size");
}

TEST(KinematicShell, SchemaDocumentsEveryParameter) {
  const auto schema = KinematicShell::schema().json();
  for (const char* field : {"mesh", "transform", "surface_density", "motion"})
    EXPECT_TRUE(schema.at("fields").contains(field)) << field;
  const auto& motion = schema.at("fields").at("motion");
  EXPECT_EQ(motion.at("kind"), "variant");
  for (const char* option : {"static", "keyframes", "analytic", "wave"})
    EXPECT_TRUE(motion.at("options").contains(option)) << option;
  EXPECT_EQ(motion.at("options").at("keyframes").at("fields").at("keys").at("min_items"), 2);
}

TEST(KinematicShellPlugin, EntryPointDescribesAndCreatesTheSolid) {
  const auto file =
      std::filesystem::path(shellflow::test_paths::plugin_dir()) / "shellflow_kinematic_shell.so";
  void* library = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(library, nullptr) << dlerror();
  const auto entry = reinterpret_cast<ShellflowPluginEntry>(dlsym(library, SHELLFLOW_ENTRY_SYMBOL));
  ASSERT_NE(entry, nullptr);
  const ShellflowPluginDescriptor* d = entry();
  EXPECT_STREQ(d->name, "kinematic_shell");
  EXPECT_EQ(d->kind, SHELLFLOW_KIND_SOLID);
  EXPECT_EQ(Json::parse(d->param_schema_json()),
            Json::parse(KinematicShell::schema().json().dump()));
  ShellflowCreateError error{};
  void* instance = d->create(keyframe_params().dump().c_str(),
                             sdk::context_to_json(context("cup")).dump().c_str(), &error);
  ASSERT_NE(instance, nullptr) << error.message;
  EXPECT_EQ(static_cast<sdk::SolidSolver*>(instance)->surfaces()[0].name, "cup");
  d->destroy(instance);
  Json bad = keyframe_params();
  bad["motion"]["keys"][1]["time"] = 0;
  EXPECT_EQ(d->create(bad.dump().c_str(), sdk::context_to_json(context()).dump().c_str(), &error),
            nullptr);
  EXPECT_STREQ(error.json_path, "/motion/keys/1/time");
  dlclose(library);
}

}  // namespace
}  // namespace shellflow::kinematic_shell
