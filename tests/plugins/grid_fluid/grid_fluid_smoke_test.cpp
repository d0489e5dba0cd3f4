// Smoke physics and the node/face scheme without shells: buoyancy's known answer, a hot
// plume rises, sources switch off on time, inviscid Taylor–Green energy rises with
// resolution (§4.2), save/restore is bit exact, fields() describes the node layout; a
// source that can set no cell of the domain is refused by name.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "grid_fluid_test_support.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;
using ::testing::HasSubstr;
constexpr double kPi = std::numbers::pi;

TEST(SmokeForces, BuoyancyIsMinusAlphaRhoPlusBetaTemperatureExcess) {
  const grid::UniformGrid g(Eigen::Vector3d::Zero(), 0.1, Eigen::Vector3i(2, 2, 2));
  NodeFields f(g, 300.0);
  f.density()[0] = 2.0;
  f.temperature()[0] = 350.0;
  BuoyancyParameters p;
  p.density_alpha = 0.5;
  p.temperature_beta = 0.01;
  p.ambient_temperature = 300.0;
  p.up = Eigen::Vector3d(0, 0, 2);  // normalised inside
  const double fmax = SmokeForces(g).add_buoyancy(f, 0.1, p, true);
  // f = −0.5·2 + 0.01·50 = −0.5 along +z; Δu = 0.1 f. Round-off only (1e-15).
  EXPECT_NEAR(f.velocity(2)[0], -0.05, 1e-15);
  EXPECT_EQ(f.velocity(1)[0], 0.0);
  EXPECT_NEAR(fmax, 0.5, 1e-15);
  EXPECT_EQ(f.velocity(2)[1], 0.0);  // no smoke, ambient: no force
  // Without the temperature field only −αρ acts.
  NodeFields h(g, 300.0);
  h.density()[0] = 2.0;
  h.temperature()[0] = 350.0;
  SmokeForces(g).add_buoyancy(h, 0.1, p, false);
  EXPECT_NEAR(h.velocity(2)[0], -0.1, 1e-15);
  // A scene whose sources set no temperature stores none: its samples carry the ambient
  // temperature, and buoyancy is −αρ alone whatever the flag says.
  NodeFields cold(g, 300.0, true, false);
  EXPECT_FALSE(cold.has_temperature());
  EXPECT_EQ(cold.field_count(), 4);
  cold.density()[0] = 2.0;
  EXPECT_EQ(cold.sample(0)[4], 300.0);
  cold.set(1, cold.sample(0));
  EXPECT_EQ(cold.density()[1], 2.0);
  SmokeForces(g).add_buoyancy(cold, 0.1, p, true);
  EXPECT_NEAR(cold.velocity(2)[0], -0.1, 1e-15);
}

TEST(SmokeSource, CylinderSetsExactlyTheNodesWithinItsRadiusAndEnds) {
  // A tilted nozzle on a 20³ grid: every node is inside iff its projection on the axis
  // falls between the ends and its distance to the axis is at most the radius.
  const grid::UniformGrid g(Eigen::Vector3d::Zero(), 0.05, Eigen::Vector3i(20, 20, 20));
  const Eigen::Vector3d from(0.2, 0.3, 0.5), to(0.7, 0.6, 0.5);
  const SmokeSource source({{"shape", "cylinder"}, {"from", {0.2, 0.3, 0.5}},
                            {"to", {0.7, 0.6, 0.5}}, {"radius", 0.12}, {"density", 2.0},
                            {"velocity", {3, 0, 0}}},
                           "/sources/0");
  NodeFields fields(g, 298.0);
  const std::int64_t set = source.apply(0.0, g, fields, false);
  std::int64_t expected = 0;
  const Eigen::Vector3d axis = to - from;
  for (std::int64_t i = 0; i < g.size(grid::Location::Node); ++i) {
    const Eigen::Vector3d p = g.position(grid::Location::Node, i);
    const double s = (p - from).dot(axis) / axis.squaredNorm();
    const bool inside = s >= 0 && s <= 1 && (p - from - s * axis).norm() <= 0.12;
    expected += inside;
    EXPECT_EQ(fields.density()[i], inside ? 2.0 : 0.0) << "node " << i;
  }
  EXPECT_EQ(set, expected);
  EXPECT_GT(set, 50);
  // Its velocity goes on the faces of its cells (centres inside), not on the nodes: every
  // x-face with an emitter cell on either side, the intake ones (emitter cell on the +
  // side only, flow +x) closed when asked.
  const auto emitter_cell = [&](const Eigen::Vector3i& c) {
    if ((c.array() < 0).any() || (c.array() >= g.cells().array()).any()) return false;
    const Eigen::Vector3d p = g.position(grid::Location::Cell, c);
    const double s = (p - from).dot(axis) / axis.squaredNorm();
    return s >= 0 && s <= 1 && (p - from - s * axis).norm() <= 0.12;
  };
  for (const bool closed_intake : {false, true}) {
    std::vector<SourceFace> faces;
    source.append_faces(0.0, g, 0, closed_intake, faces);
    std::int64_t listed = 0, intake = 0;
    for (std::int64_t f = 0; f < g.size(grid::Location::FaceX); ++f) {
      const Eigen::Vector3i plus = g.coordinates(grid::Location::FaceX, f);
      const bool in_plus = emitter_cell(plus);
      const bool in_minus = emitter_cell(plus - Eigen::Vector3i::UnitX());
      if (!in_plus && !in_minus) continue;
      ++listed;
      const bool is_intake = in_plus && !in_minus;
      intake += is_intake;
      const auto it = std::find_if(faces.begin(), faces.end(),
                                   [&](const SourceFace& sf) { return sf.face == f; });
      ASSERT_NE(it, faces.end()) << "face " << f;
      EXPECT_EQ(it->velocity.x(), closed_intake && is_intake ? 0.0 : 3.0);
    }
    EXPECT_EQ(static_cast<std::int64_t>(faces.size()), listed);
    EXPECT_GT(intake, 10);
  }
  EXPECT_EQ(fields.velocity(0)[g.index(grid::Location::Node, 9, 9, 10)], 0.0);
}

TEST(SmokeSource, ASourceThatSetsNoCellIsRefusedNamingItsPath) {
  // Each source lies wholly outside the domain [0, 1]³ or only touches a face: validate
  // refuses it at its own path, after a valid source at /0, with its extent and the
  // domain's.
  const nlohmann::json inside = {{"shape", "sphere"}, {"center", {0.5, 0.5, 0.5}}, {"radius", 0.2}};
  const std::vector<std::pair<nlohmann::json, std::string>> cases = {
      {{{"shape", "sphere"}, {"center", {0.5, -0.5, 0.5}}, {"radius", 0.2}},
       "the sphere emitter (bounds [(0.3, -0.7, 0.3), (0.7, -0.3, 0.7)])"},
      // On the lid y = 1: no volume shared.
      {{{"shape", "box"}, {"min", {0, 1, 0}}, {"max", {1, 1.5, 1}}},
       "the box emitter (bounds [(0, 1, 0), (1, 1.5, 1)])"},
      {{{"shape", "cylinder"}, {"from", {-1, 0.5, 0.5}}, {"to", {-0.5, 0.5, 0.5}}, {"radius", 0.1}},
       "the cylinder emitter (bounds [(-1.1, 0.4, 0.4), (-0.4, 0.6, 0.6)])"},
  };
  for (const auto& [source, shape] : cases) {
    SCOPED_TRACE(source.dump());
    const std::string message =
        test::validate_refusal({{"resolution", 8}, {"sources", {inside, source}}});
    EXPECT_THAT(message, HasSubstr(std::string(test::kRefusedScene) + ": /fluid/sources/1: "));
    EXPECT_THAT(message,
                HasSubstr(shape + " lies entirely outside the domain [(0, 0, 0), (1, 1, 1)], "
                                  "so it would never set any smoke"));
  }
}

TEST(SmokeSource, ASourcePartlyOutsideTheDomainIsAcceptedAndSetsSmoke) {
  // A nozzle through the floor (fed from below) and a ball centred on a face are inside
  // in part: accepted, and their first step sets the nodes inside.
  const std::vector<nlohmann::json> sources = {
      {{"shape", "box"},
       {"min", {0.4, -0.2, 0.4}},
       {"max", {0.6, 0.1, 0.6}},
       {"velocity", {0, 1, 0}}},
      {{"shape", "sphere"}, {"center", {1, 0.5, 0.5}}, {"radius", 0.2}},
  };
  for (const auto& source : sources) {
    SCOPED_TRACE(source.dump());
    std::unique_ptr<GridFluid> fluid;
    ASSERT_NO_THROW(fluid = test::make_fluid({{"resolution", 8}, {"sources", {source}}}));
    fluid->advect(0.0, 0.01, {}, {});
    EXPECT_GT(fluid->last_step().source_nodes, 0);
  }
}

TEST(GridFluidSmoke, HotPlumeRisesAndTheSourceTurnsOff) {
  auto fluid = test::make_fluid(
      {{"resolution", 16},
       {"boundary", {{"y_max", {{"type", "open"}}}}},
       {"smoke", {{"temperature_buoyancy", 0.01}, {"vorticity_confinement", 0.3}}},
       {"sources", nlohmann::json::array({{{"shape", "sphere"},
                                           {"center", {0.5, 0.2, 0.5}},
                                           {"radius", 0.12},
                                           {"temperature", 400.0},
                                           {"density", 1.0},
                                           {"end", 0.25}}})}});
  ASSERT_TRUE(fluid->temperature_enabled());
  const double dt = 0.02;
  double t = 0.0;
  for (int step = 0; step < 20; ++step) {
    fluid->advect(t, dt, {}, {});
    fluid->project(dt, {}, {});
    t += dt;
  }
  // Above the source the smoke moves up (buoyancy along −gravity = +y).
  const auto& g = fluid->grid();
  const std::int64_t above = g.index(Location::Node, 8, 6, 8);
  EXPECT_GT(fluid->nodes().velocity(1)[above], 0.01);
  EXPECT_GT(fluid->nodes().density()[g.index(Location::Node, 8, 5, 8)], 0.0);
  EXPECT_LE(fluid->last_step().projection.max_relative_divergence, 1e-6);
  EXPECT_EQ(fluid->last_step().source_nodes, 0);  // off after 0.25 s
  EXPECT_FALSE(fluid->find_nonfinite().has_value());
}

/// A jet: a cylinder emitter blowing +x at 2 m/s into a 1.5 x 1 x 1 m box with a wall at
/// x_min (behind the nozzle) and the other sides `open` or walls; 40 steps at CFL 0.5.
struct JetRun {
  double max_speed = 0.0;     ///< largest |u| on any face over the run [m/s]
  double net_outflow = 0.0;   ///< volume leaving through the domain sides, last step [m^3/s]
  double emitted = 0.0;       ///< v × area of the emitter's exit faces [m^3/s]
  double max_divergence = 0;  ///< the last projection's, relative to max|u|
};

JetRun run_jet(bool open_sides) {
  const double speed = 2.0, radius = 0.2;
  const Eigen::Vector3d from(0.25, 0.5, 0.5), to(0.5, 0.5, 0.5);
  nlohmann::json boundary = nlohmann::json::object();
  if (open_sides)
    for (const char* side : {"x_max", "y_min", "y_max", "z_min", "z_max"})
      boundary[side] = {{"type", "open"}};
  auto fluid = test::make_fluid(
      {{"domain", {{"min", {0, 0, 0}}, {"max", {1.5, 1, 1}}}},
       {"resolution", 24},
       {"boundary", boundary},
       {"pressure", {{"tolerance", 1e-8}}},
       {"sources", nlohmann::json::array({{{"shape", "cylinder"},
                                           {"from", {from.x(), from.y(), from.z()}},
                                           {"to", {to.x(), to.y(), to.z()}},
                                           {"radius", radius},
                                           {"velocity", {speed, 0, 0}}}})}},
      Eigen::Vector3d::Zero());
  const auto& g = fluid->grid();
  const double dx = g.dx();
  const double dt = 0.5 * dx / speed;
  JetRun out;
  for (int step = 0; step < 40; ++step) {
    fluid->advect(step * dt, dt, {}, {});
    fluid->project(dt, {}, {});
    out.max_speed = std::max(out.max_speed, fluid->mac().max_face_speed());
  }
  out.max_divergence = fluid->last_step().projection.max_relative_divergence;
  // Outflow through the six sides (walls carry 0).
  const Eigen::Vector3i n = g.cells();
  for (int a = 0; a < 3; ++a) {
    const auto& u = fluid->mac().face_velocity(a);
    for (std::int64_t f = 0; f < static_cast<std::int64_t>(u.size()); ++f) {
      const Eigen::Vector3i ijk = g.coordinates(face_location(a), f);
      if (ijk[a] == 0) out.net_outflow -= u[f] * dx * dx;
      if (ijk[a] == n[a]) out.net_outflow += u[f] * dx * dx;
    }
  }
  // Exit faces: an emitter cell (centre inside) whose +x neighbour is not one.
  const auto inside = [&](const Eigen::Vector3d& p) {
    const double s = (p.x() - from.x()) / (to.x() - from.x());
    return s >= 0 && s <= 1 && (p - Eigen::Vector3d(p.x(), from.y(), from.z())).norm() <= radius;
  };
  for (std::int64_t c = 0; c < g.size(Location::Cell); ++c) {
    const Eigen::Vector3d p = g.position(Location::Cell, c);
    if (inside(p) && !inside(p + Eigen::Vector3d(dx, 0, 0))) out.emitted += speed * dx * dx;
  }
  return out;
}

TEST(GridFluidSmoke, JetEmitterAddsItsVolumeWithoutDrawingAirAroundItsBack) {
  // With open sides the emitter is a nozzle fed from outside: what leaves the box is
  // exactly what its exit faces emit (to the 1e-8 solve), and no air rushes around its
  // intake rim. Measured: max |u| 1.12x the jet's, at the jet's head (the air it pushes).
  // With the velocity also set on the nodes, or with the nodes touching held faces giving
  // their increments to the free faces (§4.2), the jet leaked onto the faces about the
  // rim every step: max |u| reached 2.1x (open) and 1.7x (closed) there.
  const JetRun open = run_jet(true);
  std::printf("open jet: max |u| %.4f m/s (jet 2), outflow %.6f, emitted %.6f m^3/s\n",
              open.max_speed, open.net_outflow, open.emitted);
  EXPECT_GT(open.emitted, 0.0);
  EXPECT_NEAR(open.net_outflow, open.emitted, 1e-6 * open.emitted);  // solve tolerance 1e-8
  EXPECT_LE(open.max_divergence, 1e-6);
  EXPECT_LE(open.max_speed, 1.2 * 2.0);
  // Sealed in walls, the emitter cannot add volume: it draws the air it blows (no net
  // flow, round-off only). Measured: max |u| 1.10x the jet's.
  const JetRun closed = run_jet(false);
  std::printf("closed jet: max |u| %.4f m/s, outflow %.3g m^3/s\n", closed.max_speed,
              closed.net_outflow);
  EXPECT_NEAR(closed.net_outflow, 0.0, 1e-12 * open.emitted);
  EXPECT_LE(closed.max_divergence, 1e-6);
  EXPECT_LE(closed.max_speed, 1.2 * 2.0);
}

// Inviscid Taylor–Green vortex in the symmetry cell [0, π]^3 (free-slip walls):
// u = sin x cos y cos z, v = −cos x sin y cos z, w = 0. Returns KE(T)/KE(0).
double taylor_green_energy_kept(int resolution, double end_time) {
  auto fluid = test::make_fluid({{"domain", {{"min", {0, 0, 0}}, {"max", {kPi, kPi, kPi}}}},
                                 {"resolution", resolution},
                                 {"pressure", {{"tolerance", 1e-8}}}},
                                Eigen::Vector3d::Zero());
  const auto& g = fluid->grid();
  for (int a = 0; a < 2; ++a) {
    auto& u = fluid->mac().face_velocity(a);
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(u.size()); ++i) {
      const Eigen::Vector3d p = g.position(face_location(a), i);
      u[i] = a == 0 ? std::sin(p.x()) * std::cos(p.y()) * std::cos(p.z())
                    : -std::cos(p.x()) * std::sin(p.y()) * std::cos(p.z());
    }
  }
  const auto energy = [&] {
    double e = 0.0;
    for (int a = 0; a < 3; ++a)
      for (const double u : fluid->mac().face_velocity(a)) e += 0.5 * u * u;
    return e * std::pow(g.dx(), 3);
  };
  fluid->project(1.0, {}, {});
  const double e0 = energy();
  const double dt = 0.5 * g.dx();  // CFL 0.5 at max|u| = 1
  const int steps = static_cast<int>(std::ceil(end_time / dt));
  for (int s = 0; s < steps; ++s) {
    fluid->advect(s * dt, end_time / steps, {}, {});
    fluid->project(end_time / steps, {}, {});
  }
  return energy() / e0;
}

TEST(GridFluidSmoke, TaylorGreenEnergyKeptRisesWithResolution) {
  const double k12 = taylor_green_energy_kept(12, 1.0);
  const double k16 = taylor_green_energy_kept(16, 1.0);
  const double k24 = taylor_green_energy_kept(24, 1.0);
  std::printf("Taylor-Green KE(1)/KE(0): 12^3 %.4f, 16^3 %.4f, 24^3 %.4f\n", k12, k16, k24);
  RecordProperty("ke_kept_12", std::to_string(k12));
  RecordProperty("ke_kept_16", std::to_string(k16));
  RecordProperty("ke_kept_24", std::to_string(k24));
  EXPECT_LT(k12, k16);
  EXPECT_LT(k16, k24);
  // Semi-Lagrangian advection and a projection only remove energy (the exact inviscid
  // answer is 1); 1e-9 allows round-off.
  EXPECT_LE(k24, 1.0 + 1e-9);
}

TEST(GridFluidSmoke, SaveRestoreIsBitExact) {
  auto fluid = test::make_fluid(
      {{"resolution", 12},
       {"sources", nlohmann::json::array({{{"shape", "box"},
                                           {"min", {0.3, 0.1, 0.3}},
                                           {"max", {0.7, 0.3, 0.7}},
                                           {"velocity", {0.0, 1.0, 0.2}}}})}});
  const auto plate = test::make_plate({0.5, 0.6, 0.5}, Eigen::Vector3d(0.2, 1, 0).normalized(), 0.5, 6);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v{plate.velocities};
  const auto step = [&](double t) {
    fluid->advect(t, 0.02, shells, shells);
    fluid->project(0.02, shells, v);
  };
  step(0.0);
  sdk::StateBuffer saved;
  sdk::StateWriter out(saved);
  fluid->save(out);
  step(0.02);
  const auto first = fluid->mac().face_velocity(1);
  const auto first_rho = fluid->nodes().density();
  sdk::StateReader in(saved);
  fluid->restore(in);
  EXPECT_TRUE(in.at_end());
  step(0.02);
  EXPECT_EQ(first, fluid->mac().face_velocity(1));
  EXPECT_EQ(first_rho, fluid->nodes().density());
}

TEST(GridFluidSmoke, FieldsDescribeTheNodeLayout) {
  auto fluid = test::make_fluid({{"domain", {{"min", {-1, 0, 0}}, {"max", {1, 1, 0.5}}}},
                                 {"resolution", 8}});
  fluid->nodes().density()[fluid->grid().index(Location::Node, 3, 2, 1)] = 0.75;
  const auto views = fluid->fields();
  ASSERT_GE(views.size(), 3u);
  const auto& d = views[0];
  EXPECT_EQ(d.name, "density");
  EXPECT_EQ(d.dims, (std::array<int, 3>{9, 5, 3}));  // nodes of 8 x 4 x 2 cells
  EXPECT_DOUBLE_EQ(d.dx, 0.25);
  EXPECT_TRUE(d.origin.isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_EQ(d.data[0][3 + 9 * (2 + 5 * 1)], 0.75);  // the documented FieldView layout
  EXPECT_EQ(views[1].name, "velocity");
  EXPECT_EQ(views[1].components, 3);
}

}  // namespace
}  // namespace shellflow::grid_fluid
