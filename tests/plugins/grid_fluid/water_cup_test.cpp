// A kinematic cup (§3, §4.3, §4.4.1; Guendelman et al. 2005): an open cylinder with a bottom
// holds water while still, none of it below the rim outside the cup, and pours it out
// when tipped about a horizontal axis through its rim (the water core issue's cup case;
// the scene is configs/verify/water_kinematic_cup.json). Keeping the water of a column that
// collapses in the cup fails today and is disabled (--gtest_also_run_disabled_tests): see
// its note.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>

#include "grid_fluid_test_support.hpp"
#include "shellflow/geometry/shell_band.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

// A 1 x 1 x 0.5 m tank at 32 x 32 x 16 cells (Δx = 1/32): the cup is R = 5.4Δx, H = 8.6Δx,
// its base and axis between node planes; tipped, it stays inside the tank.
constexpr int kResolution = 32;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kRadius = 0.17;
constexpr double kHeight = 0.27;
constexpr int kCupSegments = 32;                ///< the polygon of the cup's wall
const Eigen::Vector3d kBase(0.33, 0.26, 0.26);  // centre of the bottom, axis +y

/// The cup's rigid pose: a rotation by `angle` about the z axis through `pivot`.
struct CupPose {
  Eigen::Vector3d pivot = kBase + Eigen::Vector3d(kRadius, kHeight, 0.0);  // rim, +x side
  double angle = 0.0;                                                      // [rad]
  double rate = 0.0;                                                       // dθ/dt [rad/s]

  Eigen::Matrix3d rotation() const {
    return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  Eigen::Vector3d place(const Eigen::Vector3d& x0) const {
    return pivot + rotation() * (x0 - pivot);
  }
  /// x in the upright cup's frame: (distance from the axis, height above the base).
  Eigen::Vector2d cup_coordinates(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d local = pivot + rotation().transpose() * (x - pivot) - kBase;
    return {std::hypot(local.x(), local.z()), local.y()};
  }
};

/// The cup's mesh, each node x0 (upright, base at the origin) at place(x0) moving at
/// velocity(place(x0)).
sdk::ShellSurface cup_surface(
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& place,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& velocity) {
  const auto mesh = geometry::make_open_cylinder(kRadius, kHeight, kCupSegments, 6, true);
  sdk::ShellSurface s;
  s.name = "cup";
  s.positions.resize(mesh.positions.rows(), 3);
  s.velocities.resize(mesh.positions.rows(), 3);
  for (Eigen::Index i = 0; i < mesh.positions.rows(); ++i) {
    const Eigen::Vector3d x = place(mesh.positions.row(i).transpose());
    s.positions.row(i) = x.transpose();
    s.velocities.row(i) = velocity(x).transpose();
  }
  s.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  s.surface_density = Eigen::VectorXd::Ones(mesh.triangles.rows());
  return s;
}

/// The cup at `pose`, its node velocities those of the rigid motion: ω × (x − pivot).
sdk::ShellSurface make_cup(const CupPose& pose) {
  const Eigen::Vector3d omega(0.0, 0.0, pose.rate);
  return cup_surface([&](const Eigen::Vector3d& x0) { return pose.place(kBase + x0); },
                     [&](const Eigen::Vector3d& x) { return omega.cross(x - pose.pivot); });
}

nlohmann::json cup_params(nlohmann::json water) {
  return {{"domain", {{"min", {0.0, 0.0, 0.0}}, {"max", {1.0, 1.0, 0.5}}}},
          {"resolution", kResolution},
          {"pressure", {{"tolerance", 1e-6}}},
          {"water", std::move(water)}};
}

/// Water inscribed in the upright cup: a box of half-side 0.7 R (inside R/√2) from just
/// above the bottom to 0.7 H.
nlohmann::json water_in_the_cup() {
  const double h = 0.7 * kRadius;
  return {{"initial",
           {{{"type", "box"},
             {"min", {kBase.x() - h, kBase.y() + 0.01, kBase.z() - h}},
             {"max", {kBase.x() + h, kBase.y() + 0.7 * kHeight, kBase.z() + h}}}}}};
}

/// Water standing in the upright cup up to `fill` of its height: the cup's own cylinder.
nlohmann::json water_standing_in_the_cup(double fill) {
  return {{"initial",
           {{{"type", "cylinder"},
             {"from", {kBase.x(), kBase.y(), kBase.z()}},
             {"to", {kBase.x(), kBase.y() + fill * kHeight, kBase.z()}},
             {"radius", kRadius}}}}};
}

struct WaterCount {
  int outside_below_rim = 0;  ///< φ <= 0 farther than Δx from the upright cup, below its rim
  int on_the_floor = 0;       ///< φ <= 0 below the upright cup's base, beyond its radius
  int in_cup = 0;             ///< φ <= 0 inside the cup at its pose
  int interior = 0;           ///< of those, farther than Δx from its wall and bottom
};

WaterCount count_water(const GridFluid& f, const CupPose& pose) {
  const auto& phi = f.liquid()->level_set().phi();
  const double dx = f.grid().dx();
  const CupPose upright{};
  WaterCount c;
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    if (phi[i] > 0.0) continue;
    const Eigen::Vector3d x = f.liquid()->level_set().grid().position(Location::Node, i);
    const Eigen::Vector2d still = upright.cup_coordinates(x);
    const bool below_rim = still.y() < kHeight;
    if (below_rim && (still.x() > kRadius + dx || still.y() < -dx)) ++c.outside_below_rim;
    if (still.y() < -dx && still.x() > kRadius + dx) ++c.on_the_floor;
    const Eigen::Vector2d now = pose.cup_coordinates(x);
    if (now.x() < kRadius && now.y() > 0.0 && now.y() < kHeight) {
      ++c.in_cup;
      if (now.x() < kRadius - dx && now.y() > dx) ++c.interior;
    }
  }
  return c;
}

/// Steps at the CFL step (0.9) from t to t_end with the cup following pose(t); returns the
/// largest count of water nodes outside the upright cup below its rim seen after a step.
int run_cup(GridFluid& f, double& t, double t_end, const std::function<CupPose(double)>& pose) {
  int worst_outside = 0;
  while (t < t_end - 1e-12) {
    const double dt = std::min(f.stable_dt(0.9), t_end - t);
    const std::vector<sdk::ShellSurface> s0{make_cup(pose(t))}, s1{make_cup(pose(t + dt))};
    f.advect(t, dt, s0, s1);
    const std::vector<sdk::Positions> v_eff{s1[0].velocities};
    f.project(dt, s1, v_eff);
    t += dt;
    worst_outside = std::max(worst_outside, count_water(f, pose(t)).outside_below_rim);
  }
  return worst_outside;
}

CupPose still(double) {
  return CupPose{};
}

/// The stream: a cylinder emitter 0.08–0.14 m above the rim, radius 0.11 m (3.5Δx), 1 m/s
/// down, on for the first 0.3 s.
nlohmann::json stream_into_the_cup() {
  const double top = kBase.y() + kHeight;
  return {{"sources",
           {{{"shape", "cylinder"},
             {"from", {kBase.x(), top + 0.08, kBase.z()}},
             {"to", {kBase.x(), top + 0.14, kBase.z()}},
             {"radius", 0.11},
             {"velocity", {0.0, -1.0, 0.0}},
             {"end", 0.3}}}}};
}

/// The still cup's tests hold on the level set alone ("cells") and with a volume fraction
/// ("fraction"), with the same bounds.
class StillCup : public ::testing::TestWithParam<const char*> {
 protected:
  nlohmann::json params(nlohmann::json water) const {
    return cup_params(test::water_core(GetParam(), std::move(water)));
  }
};

INSTANTIATE_TEST_SUITE_P(Layouts, StillCup, ::testing::Values("cells", "fraction"),
                         [](const auto& info) { return std::string(info.param); });

TEST_P(StillCup, StreamFillingTheStillCupNeverRunsOutsideIt) {
  // The wall and the bottom seal the cup (§3, §4.3, §4.4.1): through the fill and 1.2 s
  // after it, no node outside the cup below its rim ever holds water (exact: a count).
  auto fluid = test::make_fluid(params(stream_into_the_cup()));
  double t = 0.0;
  int worst_outside = run_cup(*fluid, t, 0.3, still);
  const WaterCount filled = count_water(*fluid, CupPose{});
  worst_outside = std::max(worst_outside, run_cup(*fluid, t, 1.5, still));
  EXPECT_EQ(worst_outside, 0);
  // Not vacuous: the stream reached the cup (the first centimetres of water lie in it).
  EXPECT_GT(filled.in_cup, 0);
}

TEST_P(StillCup, WaterInTheStillCupNeverRunsOutsideIt) {
  // Water inscribed in the cup falls the last centimetre and spreads to the wall.
  auto fluid = test::make_fluid(params(water_in_the_cup()));
  ASSERT_GT(count_water(*fluid, CupPose{}).interior, 0);
  double t = 0.0;
  EXPECT_EQ(run_cup(*fluid, t, 1.5, still), 0);  // exact: a count, as above
}

TEST_P(StillCup, WaterFillingTheStillCupStaysStill) {
  // Water standing in the cup to half its height, its side on the cup's wall: hydrostatic
  // rest is the discrete solution (§4.3, §4.4.1), so it stays still and keeps its volume.
  // Until 6 Dec 2026 the first φ held the water's side as a surface next to the wall
  // (nodes within a tenth of a cell of it, and those by the bottom's rim, whose central
  // differences mix two faces), the surface row next to the wall read a cell low, and
  // stray currents of up to 0.4 m/s stirred the cup (+0.36% of volume in 1.5 s).
  auto fluid = test::make_fluid(params(water_standing_in_the_cup(0.5)));
  double t = 0.0, fastest = 0.0;
  int worst_outside = 0;
  double v0 = 0.0;
  for (const double until : {0.5, 1.0, 1.5}) {
    worst_outside = std::max(worst_outside, run_cup(*fluid, t, until, still));
    if (v0 == 0.0)
      v0 = test::reported(*fluid, "water_volume") - test::reported(*fluid, "water_volume_change");
    fastest = std::max(fastest, fluid->mac().max_face_speed());
  }
  const double v1 = test::reported(*fluid, "water_volume");
  std::printf("[  figure  ] box collapsing in the cup, 1.5 s: φ's volume %+.3f%%\n",
              100.0 * (v1 / v0 - 1.0));
  RecordProperty("max_face_speed", std::to_string(fastest));
  std::printf("[  figure  ] water filling the still cup: %.3e m/s at most, volume %+.2e\n", fastest,
              v1 / v0 - 1.0);
  EXPECT_EQ(worst_outside, 0);  // exact: a count, as above
  // Bounds from the projection's relative tolerance, 1e-6 (cup_params): of the speed scale
  // √(gΔx) the solve resolves, and of a cell's height of the level over the cup's section.
  const double dx = fluid->grid().dx();
  EXPECT_LE(fastest, 1e-6 * std::sqrt(9.81 * dx));
  EXPECT_NEAR(v1, v0, 1e-6 * dx * std::numbers::pi * kRadius * kRadius);
}

TEST(WaterCup, TheWaterStandingInTheCupIsReadWhereverTheCupStands) {
  // The volume measure (Liquid::volume) of water standing in the cup to half its height,
  // φ the level's plane inside the cup's 32-gon and a band's depth of air outside it and
  // below its bottom, with the cup at eight places and turns against the grid: the known
  // answer is the polygon's section times the depth. The cells by the bottom's rim are cut
  // by the wall and the bottom; read by the plane of whichever was nearer their centre,
  // each read up to half a cell off, and the reading jumped as the cup moved.
  const auto fluid =
      test::make_fluid(cup_params(test::water_core("cells", nlohmann::json::object())));
  const grid::UniformGrid& grid = fluid->grid();
  const double dx = grid.dx(), band_depth = fluid->liquid()->level_set().band();
  const double apothem = kRadius * std::cos(std::numbers::pi / kCupSegments);
  const double depth = 0.5 * kHeight;
  const double exact = 0.5 * kCupSegments * kRadius * kRadius *
                       std::sin(2.0 * std::numbers::pi / kCupSegments) * depth;
  double lowest = kInfinity, highest = -kInfinity;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d base =
        kBase + dx * Eigen::Vector3d(std::fmod(0.137 * k, 1.0), std::fmod(0.173 * k, 1.0),
                                     std::fmod(0.291 * k, 1.0));
    const double turn = 0.037 * k;  // [rad] about the axis; a facet spans 0.196
    const Eigen::Matrix3d r = Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const sdk::ShellSurface cup =
        cup_surface([&](const Eigen::Vector3d& x0) { return Eigen::Vector3d(base + r * x0); },
                    [](const Eigen::Vector3d&) { return Eigen::Vector3d::Zero().eval(); });
    auto& phi = fluid->liquid()->level_set().phi();
    const grid::UniformGrid& lattice = fluid->liquid()->level_set().grid();
    for (std::int64_t i = 0; i < lattice.size(Location::Node); ++i) {
      const Eigen::Vector3d local = r.transpose() * (lattice.position(Location::Node, i) - base);
      // The generator's vertices lie at angles 2πs/n, at (R cos θ, ·, −R sin θ).
      const double angle = std::atan2(-local.z(), local.x());
      const double facet = 2.0 * std::numbers::pi / kCupSegments;
      const double off_facet = angle - facet * std::floor(angle / facet) - 0.5 * facet;
      const bool inside =
          std::hypot(local.x(), local.z()) * std::cos(off_facet) < apothem && local.y() > 0.0;
      phi[i] = inside ? local.y() - depth : band_depth;
    }
    const std::vector<sdk::ShellSurface> shells{cup};
    const ShellGeometry geometry(shells, 1e-3 * dx);
    geometry::ShellBand band(grid);
    band.add(geometry::TriangleMesh(cup), 3.0 * dx);
    const double read = fluid->liquid()->volume(&geometry, &band) / exact - 1.0;
    lowest = std::min(lowest, read);
    highest = std::max(highest, read);
  }
  std::printf("[  figure  ] water standing in the cup at 8 places: read %+.2f … %+.2f %% off\n",
              100.0 * lowest, 100.0 * highest);
  EXPECT_GT(lowest, -0.01);
  EXPECT_LT(highest, 0.01);
}

// The inscribed box collapses in the cup: it leaves a ring of air 1.6Δx wide against the
// wall, falls into it as a dam break and shoots up the wall in a sheet thinner than the
// cells the wall cuts. On the defaults the run's volume is F's: it changes only by what F's
// bounds clip (bound 1e-4 of it, an order above the measured). φ, which the mesh shows,
// follows F's planes except in the cells the wall cuts, left to the level set (one F per cut
// cell, #52): bound a tenth of the water, above the measured (docs/measured-figures.md).
TEST(WaterCup, CollapsingWaterInTheCupKeepsItsVolume) {
  auto fluid = test::make_fluid(cup_params(water_in_the_cup()));
  const double v0 = fluid->liquid()->level_set().volume();
  double t = 0.0;
  run_cup(*fluid, t, 1.5, still);
  const double shown = fluid->liquid()->level_set().volume();
  const double drift = test::reported(*fluid, "water_volume_drift");
  std::printf("[  figure  ] box collapsing in the cup, 1.5 s: drift %+.1e, φ's volume %+.2f%%\n",
              drift / v0, 100.0 * (shown / v0 - 1.0));
  EXPECT_LT(std::abs(drift), 1e-4 * v0);
  EXPECT_NEAR(shown, v0, 0.1 * v0);
}

/// Settled for 0.5 s, then tipped 110° clockwise seen from +z (pours towards +x) about the
/// z axis through the rim in 1 s at a constant rate, then held.
CupPose tipping(double time) {
  constexpr double kStart = 0.5, kDuration = 1.0;
  const double tip = -110.0 * std::numbers::pi / 180.0;
  CupPose p;
  p.angle = std::clamp((time - kStart) / kDuration, 0.0, 1.0) * tip;
  p.rate = time >= kStart && time < kStart + kDuration ? tip / kDuration : 0.0;
  return p;
}

TEST(WaterCupSlow, TippedCupPoursItsWaterOut) {
  // The pour is a stream a cell or two thick falling 0.26 m to the floor: the trilinear φ
  // step loses it on the way (measured: 92% of the water gone, none on the floor), so this
  // case runs MacCormack's φ step (measured: 16% lost, 312 nodes of water on the floor);
  // 16 particles per cell also pour it (+18%, 167 nodes on the floor, six times slower).
  auto water = water_standing_in_the_cup(0.5);
  water["advection"] = "maccormack";
  auto fluid = test::make_fluid(cup_params(water));
  double t = 0.0;
  run_cup(*fluid, t, 0.5, tipping);
  const WaterCount before = count_water(*fluid, tipping(t));
  ASSERT_GT(before.interior, 0);
  ASSERT_EQ(before.on_the_floor, 0);
  run_cup(*fluid, t, 2.0, tipping);
  const WaterCount after = count_water(*fluid, tipping(t));
  RecordProperty("interior_before", before.interior);
  RecordProperty("interior_after", after.interior);
  EXPECT_GT(after.on_the_floor, 0);
  // Opening 20° below horizontal, the cup holds no pocket: what stays in it is a film on
  // the wall, within Δx of it. A tenth of the interior allows for water still running out
  // 0.5 s after the tip (the cup empties in about sqrt(2H/g) = 0.23 s).
  EXPECT_LE(after.interior, before.interior / 10);
}

}  // namespace
}  // namespace shellflow::grid_fluid
