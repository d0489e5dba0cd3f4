// Water (§4.3 free surface, §4.4, §4.4.1; Guendelman et al. 2005) in grid_fluid: still
// water stays still, a thin shell keeps a dry side dry, fast marching gives distances.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "grid_fluid_test_support.hpp"
#include "shellflow/grid_fluid/water/fast_marching.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/level_set_advector.hpp"
#include "shellflow/grid_fluid/water/velocity_extrapolation.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

nlohmann::json water_params(int resolution, nlohmann::json water, double tolerance = 1e-6) {
  return {{"resolution", resolution},
          {"pressure", {{"tolerance", tolerance}}},
          {"water", std::move(water)}};
}

double max_face_speed(const GridFluid& f) {
  return f.max_flow_speed();
}

using test::run_for;
using test::surface_height;

void run_steps(GridFluid& f, int steps, double dt, sdk::ShellSet shells,
               const std::vector<sdk::Positions>& v_eff) {
  double t = 0.0;
  for (int s = 0; s < steps; ++s) {
    f.advect(t, dt, shells, shells);
    f.project(dt, shells, v_eff);
    t += dt;
  }
}

TEST(Water, PoolAtRestInAClosedTankStaysAtRest) {
  // 16^3, pool up to 0.41 (between node planes), 200 steps of 0.01 s, PCG to 1e-10.
  auto fluid = test::make_fluid(
      water_params(16, {{"initial", {{{"type", "pool"}, {"height", 0.41}}}}}, 1e-10));
  const double dx = fluid->grid().dx();
  const double h0 = surface_height(*fluid, 0.5, 0.5);
  ASSERT_NEAR(h0, 0.41, 1e-9);  // φ of a plane is exact under linear interpolation
  const double v0 = fluid->liquid()->level_set().volume();
  run_steps(*fluid, 200, 0.01, {}, {});
  // The bounds: max|u| <= 1e-8 m/s (the hydrostatic state is an exact discrete
  // solution with the ghost fluid rule; PCG to 1e-10 leaves ~1e-10 g Δt per step).
  EXPECT_LE(max_face_speed(*fluid), 1e-8);
  EXPECT_NEAR(surface_height(*fluid, 0.5, 0.5), h0, 1e-3 * dx);
  EXPECT_NEAR(surface_height(*fluid, 0.2, 0.8), h0, 1e-3 * dx);
  EXPECT_NEAR(fluid->liquid()->level_set().volume(), v0, 1e-9);
  EXPECT_GT(fluid->last_step().projection.liquid_cells, 16 * 16 * 6);
  EXPECT_LT(fluid->last_step().projection.liquid_cells, 16 * 16 * 7 + 1);
  // The solve runs on the liquid's bounding box: the pool's seven cell rows.
  EXPECT_EQ(fluid->last_step().projection.solve_cells, fluid->last_step().projection.liquid_cells);
}

TEST(Water, AFallingDropFallsFreelyAndOnlyItsBoxIsSolved) {
  // A drop (r = 0.12) in a 32^3 tank, 10 steps of 0.01 s: in free fall the pressure is
  // zero and every face of the drop moves at −g t (a uniform field is advected, extended
  // and projected exactly: round-off bound). Only the nodes about the drop are advected
  // and only its bounding box is solved, not the tank.
  auto fluid = test::make_fluid(water_params(
      32, {{"initial", {{{"type", "sphere"}, {"center", {0.5, 0.6, 0.5}}, {"radius", 0.12}}}}},
      1e-8));
  run_steps(*fluid, 10, 0.01, {}, {});
  const auto& p = fluid->last_step().projection;
  const double cells_across = 2.0 * 0.12 * 32 + 2.0;  // the diameter, a cell either side
  EXPECT_GT(p.liquid_cells, 0);
  EXPECT_LE(p.solve_cells, std::pow(cells_across, 3));
  EXPECT_LT(p.solve_cells, 32 * 32 * 32 / 20);
  const auto& grid = fluid->grid();
  const auto& v = fluid->mac().face_velocity(1);
  int checked = 0;
  for (int k = 0; k < 32; ++k)
    for (int j = 1; j < 32; ++j)
      for (int i = 0; i < 32; ++i) {
        const bool liquid = fluid->projection().fluid_cell(grid.index(Location::Cell, i, j, k)) ||
                            fluid->projection().fluid_cell(grid.index(Location::Cell, i, j - 1, k));
        if (!liquid) continue;
        EXPECT_NEAR(v[grid.index(Location::FaceY, i, j, k)], -9.81 * 0.1, 1e-9);
        ++checked;
      }
  EXPECT_GT(checked, 100);
}

TEST(Water, ACylinderOfWaterHoldsItsVolume) {
  // A cylinder of water on an oblique axis (r = 0.15, length 0.5): its volume converges to
  // π r² L at second order (the interpolant's secant surface and the caps' rims, bevelled
  // by the distance: measured −1.04% at 32^3, −0.27% at 64^3; a cylinder a cell thinner
  // would be 13% smaller at 32^3), and an axis of zero length is an error that names the
  // entry's "to".
  const Eigen::Vector3d from(0.3, 0.3, 0.35), to(0.7, 0.6, 0.65);
  const double r = 0.15, exact = std::numbers::pi * r * r * (to - from).norm();
  const auto error_at = [&](int resolution) {
    auto fluid = test::make_fluid(water_params(resolution,
                                               {{"initial",
                                                 {{{"type", "cylinder"},
                                                   {"from", {from.x(), from.y(), from.z()}},
                                                   {"to", {to.x(), to.y(), to.z()}},
                                                   {"radius", r}}}}},
                                               1e-8));
    return fluid->liquid()->level_set().volume() / exact - 1.0;
  };
  const double e32 = error_at(32), e64 = error_at(64);
  std::printf("[  figure  ] cylinder volume %+.3f%% at 32^3, %+.3f%% at 64^3\n", 100.0 * e32,
              100.0 * e64);
  EXPECT_LT(std::abs(e32), 0.05);                  // the 13% of one cell, well inside
  EXPECT_LT(std::abs(e64), 0.35 * std::abs(e32));  // order 1.5 or better
  try {
    test::make_fluid(water_params(32,
                                  {{"initial",
                                    {{{"type", "cylinder"},
                                      {"from", {0.5, 0.5, 0.5}},
                                      {"to", {0.5, 0.5, 0.5}},
                                      {"radius", r}}}}},
                                  1e-8));
    ADD_FAILURE() << "a cylinder without an axis was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/water/initial/0/to");
  }
}

TEST(VelocityExtrapolation, LinearProfileContinuesALinearFieldAcrossAFlatSurface) {
  // A flat surface at y = h = 4.3Δx over 8^3 cells, u_y = 1 + 2y on the y-faces below it
  // (the known, liquid faces). The linear profile continues the field exactly (round-off)
  // on the faces within a cell above the surface, and holds that value beyond; the
  // constant profile (§4.4's ∇φ·∇u = 0) copies the last liquid face everywhere above.
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 0.125, Eigen::Vector3i(8, 8, 8));
  const double dx = grid.dx(), h = 4.3 * dx;
  LevelSet level_set(grid, 6.0 * dx);
  const grid::UniformGrid& lattice = level_set.grid();  // the cell centres
  for (std::int64_t i = 0; i < lattice.size(Location::Node); ++i)
    level_set.phi()[i] = lattice.position(Location::Node, i).y() - h;
  const auto field = [](double y) { return 1.0 + 2.0 * y; };
  for (const bool linear : {true, false}) {
    MacGrid mac(grid);
    std::array<std::vector<std::uint8_t>, 3> known;
    for (int a = 0; a < 3; ++a) known[a].assign(grid.size(face_location(a)), a == 1 ? 0 : 1);
    auto& v = mac.face_velocity(1);
    for (std::int64_t f = 0; f < grid.size(Location::FaceY); ++f) {
      const double y = grid.position(Location::FaceY, f).y();
      if (y < h) {
        v[f] = field(y);
        known[1][f] = 1;
      }
    }
    VelocityExtrapolation(grid, linear)
        .extrapolate(mac, known, level_set, 5.0 * dx, ShellGeometry(), nullptr);
    const double last = field(4.0 * dx);  // the highest liquid face
    for (std::int64_t f = 0; f < grid.size(Location::FaceY); ++f) {
      const double y = grid.position(Location::FaceY, f).y();
      if (y < h || y - h > 5.0 * dx) continue;
      const double expected = !linear ? last : y - h < dx ? field(y) : field(5.0 * dx);
      EXPECT_NEAR(v[f], expected, 1e-12) << (linear ? "linear" : "constant") << " at y = " << y;
    }
  }
}

/// The exact volume of {x in the box [lo, hi] : n·x < d} for n with no zero component:
/// the inclusion-exclusion over the box's corners of the corner simplices
/// (d − n·v)³₊ / (6 |n_x n_y n_z|), each axis with a negative component mirrored.
double half_space_volume_in_box(Eigen::Vector3d n, double d, const Eigen::Vector3d& lo,
                                const Eigen::Vector3d& hi) {
  Eigen::Vector3d size = hi - lo;
  d -= n.dot(lo);  // the box's lower corner at the origin
  for (int a = 0; a < 3; ++a)
    if (n[a] < 0.0) {  // x_a → size_a − x_a
      d -= n[a] * size[a];
      n[a] = -n[a];
    }
  double sum = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    Eigen::Vector3d v;
    int upper = 0;
    for (int a = 0; a < 3; ++a) {
      const bool up = corner >> a & 1;
      v[a] = up ? size[a] : 0.0;
      upper += up;
    }
    const double reach = std::max(0.0, d - n.dot(v));
    sum += (upper % 2 ? -1.0 : 1.0) * reach * reach * reach;
  }
  return sum / (6.0 * n.x() * n.y() * n.z());
}

TEST(LevelSet, ACellsFractionIsExactForAFlatSurfaceAtAnyAngle) {
  // φ = n·x − d is linear, so its piecewise-linear interpolant on the lattice of cell
  // centres is φ itself: the lattice cells' fractions (LevelSet::cell_fraction, what
  // volume() sums) must add up to the half-space's volume in the box between the outer
  // centres to round-off, at any angle and offset. (Beyond the outer centres φ continues
  // constant: the level surfaces' test in water_cells_test.)
  const grid::UniformGrid mac(Eigen::Vector3d(0.1, -0.2, 0.3), 0.05, Eigen::Vector3i(12, 10, 14));
  const grid::UniformGrid lattice = LevelSet::cell_centre_lattice(mac);
  const double dx = lattice.dx();
  const Eigen::Vector3d lo = lattice.origin(), hi = lo + dx * lattice.cells().cast<double>();
  const std::array<Eigen::Vector3d, 4> normals = {
      Eigen::Vector3d(0.3, 0.9, 0.2), Eigen::Vector3d(-0.7, 0.1, 0.5),
      Eigen::Vector3d(0.05, -0.4, -0.9), Eigen::Vector3d(1.0, 1.0, 1.0)};
  for (const Eigen::Vector3d& direction : normals)
    for (const double offset : {-0.11, 0.0, 0.173}) {
      const Eigen::Vector3d n = direction.normalized();
      const double d = n.dot(0.5 * (lo + hi)) + offset;
      double sum = 0.0;
      for (std::int64_t c = 0; c < lattice.size(Location::Cell); ++c) {
        const Eigen::Vector3i ijk = lattice.coordinates(Location::Cell, c);
        std::array<double, 8> corner;
        for (int k = 0; k < 8; ++k)
          corner[k] = n.dot(lattice.position(Location::Node, ijk + corner_step(k))) - d;
        sum += LevelSet::cell_fraction(corner);
      }
      EXPECT_NEAR(sum * dx * dx * dx, half_space_volume_in_box(n, d, lo, hi),
                  1e-12 * (hi - lo).prod())
          << direction.transpose();
    }
}

TEST(Water, EveryFaceOfTheNextLiquidCellsHasItsNodesAdvected) {
  // Velocities are advected only on Liquid::velocity_nodes (from φ^n). The claim: every
  // face next to a liquid cell of step n+1 (what the projection reads) takes increments
  // only from such nodes. Checked on a collapsing column, where the surface moves fastest.
  auto fluid = test::make_fluid(water_params(
      16, {{"initial", {{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.3, 0.7, 2}}}}}}));
  const auto& grid = fluid->grid();
  const Eigen::Vector3i cells = grid.cells();
  double t = 0.0;
  int checked = 0;
  for (int s = 0; s < 40; ++s) {
    const double dt = fluid->stable_dt(0.9);
    const auto nodes = fluid->liquid()->velocity_nodes(t, dt, fluid->mac().max_face_speed());
    const std::vector<std::uint8_t> advected(nodes.begin(), nodes.end());
    fluid->advect(t, dt, {}, {});
    fluid->project(dt, {}, {});
    t += dt;
    if (advected.empty()) continue;  // every node was advected
    for (std::int64_t c = 0; c < grid.size(Location::Cell); ++c) {
      if (!fluid->projection().fluid_cell(c)) continue;
      const Eigen::Vector3i ijk = grid.coordinates(Location::Cell, c);
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          Eigen::Vector3i f = ijk;
          f[a] += side;
          if (f[a] == 0 || f[a] == cells[a]) continue;  // walls: fixed, no increment
          const int b = (a + 1) % 3, d = (a + 2) % 3;
          for (int db = 0; db < 2; ++db)
            for (int dd = 0; dd < 2; ++dd) {
              Eigen::Vector3i node = f;
              node[b] += db;
              node[d] += dd;
              EXPECT_EQ(advected[grid.index(Location::Node, node)], 1)
                  << "step " << s << " node " << node.transpose();
              ++checked;
            }
        }
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(Water, FirstOrderSurfacePressureAlsoHoldsStillWater) {
  auto fluid = test::make_fluid(water_params(
      16,
      {{"initial", {{{"type", "pool"}, {"height", 0.41}}}}, {"surface_pressure", "first_order"}},
      1e-10));
  run_steps(*fluid, 50, 0.01, {}, {});
  EXPECT_LE(max_face_speed(*fluid), 1e-8);  // the bound, as above
}

/// The shell tests below hold on the level set alone ("cells") and with a volume fraction
/// ("fraction"), with the same bounds.
class WaterAmongShells : public ::testing::TestWithParam<const char*> {
 protected:
  nlohmann::json water(nlohmann::json initial) const {
    return test::water_core(GetParam(), {{"initial", std::move(initial)}});
  }
};

INSTANTIATE_TEST_SUITE_P(Layouts, WaterAmongShells,
                         ::testing::Values("cells", "fraction", "cut_cells"),
                         [](const auto& info) { return std::string(info.param); });

TEST_P(WaterAmongShells, PoolAtRestWithAStaticTiltedPlatePiercingTheSurface) {
  auto fluid = test::make_fluid(
      water_params(16, water({{{"type", "pool"}, {"height", 0.41}}}), 1e-10));
  const auto plate =
      test::make_plate({0.5, 0.45, 0.52}, Eigen::Vector3d(1.0, 0.3, -0.4).normalized(), 0.6, 7);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v_eff{plate.velocities};
  const double dx = fluid->grid().dx();
  const double h0 = surface_height(*fluid, 0.15, 0.5);
  run_steps(*fluid, 200, 0.01, shells, v_eff);
  EXPECT_GT(fluid->last_step().projection.shell_neumann_faces, 0);
  EXPECT_LE(max_face_speed(*fluid), 1e-8);  // the bound
  EXPECT_NEAR(surface_height(*fluid, 0.15, 0.5), h0, 1e-3 * dx);
  EXPECT_NEAR(surface_height(*fluid, 0.85, 0.5), h0, 1e-3 * dx);
}

// Two plates crossing below and through the surface (shells that meet: cells of three or four
// parts, pockets between the plates that reach no whole cell): still water stays still, as
// beside one plate.
TEST_P(WaterAmongShells, PoolAtRestPiercedByTwoCrossingPlates) {
  auto fluid =
      test::make_fluid(water_params(16, water({{{"type", "pool"}, {"height", 0.41}}}), 1e-10));
  const auto a =
      test::make_plate({0.5, 0.45, 0.52}, Eigen::Vector3d(1.0, 0.3, -0.4).normalized(), 0.6, 7);
  const auto b =
      test::make_plate({0.47, 0.43, 0.5}, Eigen::Vector3d(-0.8, 0.5, 0.3).normalized(), 0.6, 9);
  const std::vector<sdk::ShellSurface> shells{a, b};
  const std::vector<sdk::Positions> v_eff{a.velocities, b.velocities};
  const double dx = fluid->grid().dx();
  const double h0 = surface_height(*fluid, 0.15, 0.5);
  run_steps(*fluid, 100, 0.01, shells, v_eff);  // long enough for a misread pocket to stir it
  EXPECT_LE(max_face_speed(*fluid), 1e-8);      // the still pool's bound
  EXPECT_NEAR(surface_height(*fluid, 0.15, 0.5), h0, 1e-3 * dx);
  EXPECT_NEAR(surface_height(*fluid, 0.85, 0.5), h0, 1e-3 * dx);
}

/// A thin plate x = 0.5 spanning the tank (a little beyond its walls) seals it.
sdk::ShellSurface dam_plate(double x) {
  return test::make_plate({x, 0.5, 0.5}, Eigen::Vector3d::UnitX(), 1.2, 9);
}

/// Water samples (φ <= 0) on the dry side x > plate + dx.
int wet_nodes_beyond(const GridFluid& f, double plate_x) {
  const auto& phi = f.liquid()->level_set().phi();
  const grid::UniformGrid& lattice = f.liquid()->level_set().grid();
  int wet = 0;
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i)
    if (phi[i] <= 0.0 && lattice.position(Location::Node, i).x() > plate_x + f.grid().dx()) ++wet;
  return wet;
}

TEST_P(WaterAmongShells, ThinWallDamKeepsTheDrySideDry) {
  // 16^3 tank, water x < 0.5 up to 0.8 of the height, a plate at x = 0.5 + dx/3 (between
  // planes of centres), 2 s of simulated time at the CFL step.
  auto fluid = test::make_fluid(water_params(
      16, water({{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.52, 0.8, 2}}}})));
  const double dx = fluid->grid().dx();
  const double plate_x = 0.5 + dx / 3.0;
  const auto plate = dam_plate(plate_x);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v_eff{plate.velocities};
  const int steps = run_for(*fluid, 2.0, shells, v_eff);
  EXPECT_EQ(wet_nodes_beyond(*fluid, plate_x), 0);
  EXPECT_GT(fluid->liquid()->level_set().liquid_cells(), 0);
  EXPECT_GT(steps, 20);
  if (std::string(GetParam()) == "cut_cells") {
    // F too: no water in any cell, or cut cell's part, whose centre lies beyond the plate
    // (the cut column's slots are its parts right of the plate).
    const auto& fraction = fluid->liquid()->fraction().values();
    double beyond = 0.0;
    for (std::int64_t c = 0; c < fluid->grid().size(Location::Cell); ++c)
      if (fluid->grid().position(Location::Cell, c).x() > plate_x) beyond += fraction[c];
    EXPECT_EQ(beyond, 0.0);
  }
}

TEST_P(WaterAmongShells, ThinWallDamKeepsTheWetSideLevel) {
  auto fluid = test::make_fluid(water_params(
      16, water({{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.52, 0.8, 2}}}})));
  const double dx = fluid->grid().dx();
  const auto plate = dam_plate(0.5 + dx / 3.0);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v_eff{plate.velocities};
  run_for(*fluid, 2.0, shells, v_eff);
  // Wet side level: the initial 0.8 within Δx/4 (the bound).
  EXPECT_NEAR(surface_height(*fluid, 0.25, 0.5), 0.8, 0.25 * dx);
}

TEST_P(WaterAmongShells, ThinWallDamMovingSlowlyKeepsTheDrySideDry) {
  auto fluid = test::make_fluid(
      water_params(16, water({{{"type", "box"}, {"min", {-1, -1, -1}}, {"max", {0.4, 0.6, 2}}}})));
  const double speed = 0.05;  // m/s: the plate crosses about 1.6 cells in 0.5 s
  // F's after the first step (which fits F to φ among the shells), and what its sweeps made
  // since (the dilation of the projection's residual divergence, the clipping at F = 0).
  double water_volume = 0.0, made = 0.0;
  double x = 0.45;
  double t = 0.0;
  while (t < 0.5 - 1e-12) {
    const double dt = std::min(fluid->stable_dt(0.9), 0.5 - t);
    auto p0 = dam_plate(x);
    auto p1 = dam_plate(x + speed * dt);
    p0.velocities.col(0).setConstant(speed);
    p1.velocities.col(0).setConstant(speed);
    const std::vector<sdk::ShellSurface> s0{p0}, s1{p1};
    fluid->advect(t, dt, s0, s1);
    const std::vector<sdk::Positions> v_eff{p1.velocities};
    fluid->project(dt, s1, v_eff);
    if (t == 0.0 && fluid->liquid()->fraction().enabled())
      water_volume = fluid->liquid()->fraction().volume();
    if (t > 0.0 && fluid->liquid()->fraction().enabled()) {
      const VolumeFractionStats& stats = fluid->liquid()->fraction().stats();
      made += stats.divergence + stats.clipped;
    }
    x += speed * dt;
    t += dt;
  }
  EXPECT_EQ(wet_nodes_beyond(*fluid, x), 0);
  EXPECT_GT(fluid->liquid()->level_set().liquid_cells(), 0);
  if (std::string(GetParam()) == "cut_cells") {
    // F too, as the parts moved with the plate: none in a cell or a cut cell's slot whose
    // centre lies beyond the plate, nor in an extra part there; F's budget closed to
    // round-off (1e-12 of the water: sums over 4096 cells and some 30 steps), what the
    // sweeps made within the projection's tolerance (1e-6 of the water).
    const auto& fraction = fluid->liquid()->fraction();
    const grid::UniformGrid& g = fluid->grid();
    double beyond = 0.0;
    for (std::int64_t c = 0; c < g.size(Location::Cell); ++c)
      if (g.position(Location::Cell, c).x() > x) beyond += fraction.values()[c];
    const auto parts = fluid->cut_water()->parts().parts();
    for (size_t p = 0; p < parts.size(); ++p) {
      const Eigen::Vector3i corner =
          g.coordinates(Location::Cell, parts[p].cell) +
          CellParts::cell_corner(std::countr_zero(unsigned(parts[p].corners)));
      if (!parts[p].slot && g.position(Location::Node, corner).x() > x)
        beyond += fraction.part_values()[p];
    }
    EXPECT_EQ(beyond, 0.0);
    EXPECT_NEAR(fraction.volume() - water_volume, made, 1e-12 * water_volume);
    EXPECT_LE(std::abs(made), 1e-6 * water_volume);
  }
}

// Cut cells (issue #52): water above and below a level plate across a closed tank, the plate
// 0.1, 0.32, 0.68 or 0.9 of a cell above a plane of centres, so that one side of it in the cut
// cells is a far part (a virtual node) with its own pressure; through the centres (0: no part
// holds them, the level set's samples there lie on the plate and read air, and each part's φ is
// continued from its side; 1e-6) and in a plane of faces (0.5). Still water stays still: max |u|
// <= 1e-8 m/s after 0.5 s (the still pool's bound), and the water is kept to 1e-12 of it.
TEST(WaterOnCutCells, StillWaterOnBothSidesOfALevelPlateStaysStill) {
  for (const double h : {0.1, 0.32, 0.68, 0.9, 0.0, 1e-6, 0.5}) {
    auto fluid = test::make_fluid(water_params(
        16, test::water_core("cut_cells", {{"initial", {{{"type", "pool"}, {"height", 0.41}}}}}),
        1e-10));
    const double dx = fluid->grid().dx();
    const auto plate =
        test::make_plate({0.5, (3.5 + h) * dx, 0.5}, Eigen::Vector3d::UnitY(), 2.0, 9);
    const std::vector<sdk::ShellSurface> shells{plate};
    const std::vector<sdk::Positions> v_eff{plate.velocities};
    const double before = fluid->liquid()->fraction().volume();
    run_steps(*fluid, 50, 0.01, shells, v_eff);
    EXPECT_LE(max_face_speed(*fluid), 1e-8) << "h " << h;
    EXPECT_NEAR(fluid->liquid()->fraction().volume(), before, 1e-12 * before) << "h " << h;
  }
}

/// The water about a level plate at y = `plate_y` (cut into `parts`): above it left and right
/// of x = 0.5 (every whole cell above it and the parts holding the cut cells' upper corners),
/// and below it, in cells' worth.
struct WaterAboutAPlate {
  double left = 0.0, right = 0.0, below = 0.0;
  double above() const { return left + right; }
};
WaterAboutAPlate water_about_a_plate(const GridFluid& fluid, const CellParts& parts,
                                     double plate_y) {
  const grid::UniformGrid& grid = fluid.grid();
  const VolumeFraction& fraction = fluid.liquid()->fraction();
  WaterAboutAPlate out;
  std::vector<std::uint8_t> cut_cell(grid.size(Location::Cell), 0);
  const auto add = [&](std::int64_t cell, bool above, double w) {
    (above ? grid.position(Location::Cell, cell).x() < 0.5 ? out.left : out.right : out.below) += w;
  };
  for (size_t p = 0; p < parts.parts().size(); ++p) {
    const CellPart& part = parts.parts()[p];
    cut_cell[part.cell] = 1;
    add(part.cell, part.corners == 0xCC,
        part.slot ? fraction.values()[part.cell] : fraction.part_values()[p]);
  }
  for (std::int64_t c = 0; c < grid.size(Location::Cell); ++c)
    if (!cut_cell[c]) add(c, grid.position(Location::Cell, c).y() > plate_y, fraction.values()[c]);
  return out;
}

// A pool on a level plate that spans a closed tank and rises at 0.25 m/s for 1 s (issue #52,
// moving shells): the plate, started 0.1, 0.32, 0.68 or 0.9 of a cell above a plane of
// centres, crosses four planes of nodes, each time the cut cells' parts change and their
// water is carried on. The pool rides it: no water below the plate, its surface the plate's
// height plus the pool's depth (a level surface, which φ holds exactly: a hundredth of a cell
// is margin), its water in uniform motion with the plate to 1e-9 m/s (the solve's tolerance,
// 1e-10, of the speed), F's budget closed from the box's own volume (the cut cells' first share
// of it exact). Measured: docs/measured-figures.md.
TEST(WaterOnCutCells, APoolRidesARisingPlate) {
  for (const double h : {0.1, 0.32, 0.68, 0.9}) {
    const double dx = 1.0 / 16.0, depth = 0.25, speed = 0.25;
    double y = (3.5 + h) * dx;
    auto fluid = test::make_fluid(water_params(
        16,
        test::water_core(
            "cut_cells",
            {{"initial", {{{"type", "box"}, {"min", {-1, y, -1}}, {"max", {2, y + depth, 2}}}}}}),
        1e-10));
    const double water = depth;  // [m^3]: the box spans the 1 m tank's width and length
    double t = 0.0, made = 0.0, worst_speed = 0.0;
    while (t < 1.0 - 1e-12) {
      const double dt = std::min(fluid->stable_dt(0.9), 1.0 - t);
      auto p0 = test::make_plate({0.5, y, 0.5}, Eigen::Vector3d::UnitY(), 2.0, 9);
      auto p1 = test::make_plate({0.5, y + speed * dt, 0.5}, Eigen::Vector3d::UnitY(), 2.0, 9);
      p0.velocities.col(1).setConstant(speed);
      p1.velocities.col(1).setConstant(speed);
      const std::vector<sdk::ShellSurface> s0{p0}, s1{p1};
      if (t == 0.0) fluid->start(dt, s0, std::vector<sdk::Positions>{p1.velocities});
      fluid->advect(t, dt, s0, s1);
      fluid->project(dt, s1, std::vector<sdk::Positions>{p1.velocities});
      const VolumeFractionStats& stats = fluid->liquid()->fraction().stats();
      made += stats.divergence + stats.clipped;
      y += speed * dt;
      t += dt;
      worst_speed = std::max(worst_speed, max_face_speed(*fluid));
    }
    const WaterAboutAPlate end = water_about_a_plate(*fluid, fluid->cut_water()->parts(), y);
    EXPECT_EQ(end.below, 0.0) << "h " << h;
    EXPECT_NEAR(fluid->liquid()->fraction().volume() - water, made, 1e-12 * water) << "h " << h;
    EXPECT_LE(std::abs(made), 1e-6 * water) << "h " << h;
    EXPECT_NEAR(surface_height(*fluid, 0.5, 0.5), y + depth, 0.01 * dx) << "h " << h;
    EXPECT_NEAR(worst_speed, speed, 1e-9) << "h " << h;
  }
}

// A film thinner than a cell on either side of a level plate across a closed tank (issue #52,
// "Films"), the plate 0.1, 0.32, 0.68 or 0.9 of a cell above a plane of centres (its film in the
// far parts at 0.1 and 0.32, in the slots at 0.68 and 0.9): 0.2Δx thick over x < 0.5, 0.05Δx
// beyond, at rest. Its parts hold a pressure, so the step spreads as a shallow-water dam break
// would: Ritter's flux at the step, (8/27) √g h^{3/2} (a dry bed's; a wet bed a quarter as deep
// passes 1 % less), over 0.5 s carries 13.8 % of the thick half's excess across. Between a
// third of it and twice it must go (the wave is a few cells long on this grid; what went:
// docs/measured-figures.md). Read as air, the film has no velocity and none goes.
// Its water is kept to 1e-12, all above the plate. (A plate in a plane of faces, 0.5, cuts no
// cell: its film is a floor's, docs/known-limits.md.)
TEST(WaterOnCutCells, AStepInAFilmSpreadsOnEitherSideOfAPlate) {
  for (const double h : {0.1, 0.32, 0.68, 0.9}) {
    auto fluid = test::make_fluid(water_params(
        16, test::water_core("cut_cells", {{"initial", {{{"type", "pool"}, {"height", 0.03}}}}}),
        1e-10));
    const double dx = fluid->grid().dx();
    const double plate_y = (3.5 + h) * dx;
    const auto plate = test::make_plate({0.5, plate_y, 0.5}, Eigen::Vector3d::UnitY(), 2.0, 9);
    const std::vector<sdk::ShellSurface> shells{plate};
    const std::vector<sdk::Positions> v_eff{plate.velocities};
    // The parts found with a shallow pool at rest on the floor, then the pool replaced by the
    // film: φ the distance to its slab, F in the parts above the plate.
    run_steps(*fluid, 1, 0.01, shells, v_eff);
    const grid::UniformGrid& grid = fluid->grid();
    const auto thickness = [&](double x) { return (x < 0.5 ? 0.2 : 0.05); };
    auto& phi = fluid->liquid()->level_set().phi();
    auto& fraction = fluid->liquid()->fraction();
    for (std::int64_t c = 0; c < grid.size(Location::Cell); ++c) {
      const Eigen::Vector3d x = grid.position(Location::Cell, c);
      phi[c] = std::max(x.y() - plate_y - thickness(x.x()) * dx, plate_y - x.y());
      fraction.values()[c] = 0.0;
    }
    const test::CutShells cut(grid, shells);
    ASSERT_EQ(cut.parts.parts().size(), fraction.part_values().size());
    for (size_t p = 0; p < cut.parts.parts().size(); ++p) {
      const CellPart& part = cut.parts.parts()[p];
      const double w =
          part.corners == 0xCC ? thickness(grid.position(Location::Cell, part.cell).x()) : 0.0;
      (part.slot ? fraction.values()[part.cell] : fraction.part_values()[p]) = w;
    }
    const WaterAboutAPlate start = water_about_a_plate(*fluid, cut.parts, plate_y);
    ASSERT_GT(start.right, 0.0);
    run_steps(*fluid, 50, 0.01, shells, v_eff);
    const WaterAboutAPlate end = water_about_a_plate(*fluid, cut.parts, plate_y);
    const double moved = (start.left - end.left) / (start.left - start.right);
    EXPECT_GE(moved, 0.138 / 3.0) << "h " << h;
    EXPECT_LE(moved, 2.0 * 0.138) << "h " << h;
    EXPECT_NEAR(end.above(), start.above(), 1e-12 * start.above()) << "h " << h;
    EXPECT_EQ(end.below, 0.0) << "h " << h;
    const double cell = dx * dx * dx;
    EXPECT_NEAR(fraction.volume(), start.above() * cell, 1e-12 * start.above() * cell) << "h " << h;
  }
}

// The dropped box (#52): a box of water 0.4 x 0.2 x 0.4 m let go 0.1 m above a level
// plate sealing a 32-cell tank, the plate 0.1, 0.32, 0.5, 0.68 or 0.9 of a cell above a plane of
// centres. At 0.75 s, after it has splashed across the plate to the walls: at least 99 % of it
// (the bound) and no more than it is above the plate, none below, and no water faster
// than 3 √(2 g H) (the bound; H the drop from the tank's top to the plate).
TEST(WaterOnCutCellsSlow, ABoxDroppedOnALevelPlateKeepsItsWaterAboveIt) {
  for (const double h : {0.1, 0.32, 0.5, 0.68, 0.9}) {
    const double dx = 1.0 / 32, plate_y = (15.5 + h) * dx;
    auto fluid = test::make_fluid(water_params(
        32, test::water_core("cut_cells", {{"initial",
                                            {{{"type", "box"},
                                              {"min", {0.3, plate_y + 0.1, 0.3}},
                                              {"max", {0.7, plate_y + 0.3, 0.7}}}}}})));
    const auto plate = test::make_plate({0.5, plate_y, 0.5}, Eigen::Vector3d::UnitY(), 1.2, 13);
    const std::vector<sdk::ShellSurface> shells{plate};
    const std::vector<sdk::Positions> v_eff{plate.velocities};
    const test::CutShells cut(fluid->grid(), shells);
    double fastest = 0.0, t = 0.0;
    while (t < 0.75 - 1e-12) {
      const double dt = std::min(fluid->stable_dt(0.9), 0.75 - t);
      fluid->advect(t, dt, shells, shells);
      fluid->project(dt, shells, v_eff);
      fastest = std::max(fastest, max_face_speed(*fluid));
      t += dt;
    }
    ASSERT_EQ(cut.parts.parts().size(), fluid->liquid()->fraction().part_values().size());
    const double before = fluid->liquid()->initial_volume();  // as the first step settled it
    const WaterAboutAPlate end = water_about_a_plate(*fluid, cut.parts, plate_y);
    const double cell = dx * dx * dx;
    EXPECT_GE(end.above() * cell, 0.99 * before) << "h " << h;
    EXPECT_LE(end.above() * cell, 1.01 * before) << "h " << h;
    EXPECT_EQ(end.below, 0.0) << "h " << h;
    EXPECT_LE(fastest, 3.0 * std::sqrt(2.0 * 9.81 * (1.0 - plate_y))) << "h " << h;
  }
}

// Cut cells need the volume fraction (a far part has no φ sample of its own: its water is its
// F) and are not yet for particles: a scene asking otherwise is told at /fluid/water/cut_cells
// what to set.
TEST(WaterOnCutCells, AScenePairingCutCellsWithWhatTheyCannotServeIsToldWhatToSet) {
  const std::string without_fraction = test::validate_refusal(
      {{"resolution", 8}, {"water", {{"cut_cells", true}, {"volume_fraction", false}}}});
  EXPECT_NE(without_fraction.find("/fluid/water/cut_cells"), std::string::npos) << without_fraction;
  EXPECT_NE(without_fraction.find("volume_fraction true"), std::string::npos) << without_fraction;
  const std::string with_particles = test::validate_refusal(
      {{"resolution", 8}, {"water", {{"cut_cells", true}, {"particles", {{"per_cell", 8}}}}}});
  EXPECT_NE(with_particles.find("/fluid/water/cut_cells"), std::string::npos) << with_particles;
  EXPECT_NE(with_particles.find("per_cell to 0"), std::string::npos) << with_particles;
}

TEST(LevelSetAdvection, TracingOnlyNearTheWaterGivesTheSameLevelSetOnceReinitialised) {
  // LevelSetAdvector::advect's `reach`: cells farther than max |u| Δt + 2.5Δx from the water
  // keep their φ, which fast marching then sets anew. A sphere (r = 5.3Δx, off the centres)
  // in a swirling flow (|u| up to 1.3 m/s, Δt = 0.9Δx / max |u|), traced every cell or only
  // the band, then reinitialised: the same φ to the bit.
  const grid::UniformGrid mac(Eigen::Vector3d::Zero(), 1.0 / 24, Eigen::Vector3i::Constant(24));
  LevelSet level_set(mac, 6.0 * mac.dx());
  const grid::UniformGrid& lattice = level_set.grid();
  const double dx = lattice.dx();
  const Eigen::Vector3d c(0.5 + 0.31 * dx, 0.5 - 0.17 * dx, 0.5 + 0.07 * dx);
  auto& phi = level_set.phi();
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i)
    phi[i] = std::clamp((lattice.position(Location::Node, i) - c).norm() - 5.3 * dx,
                        -level_set.band(), level_set.band());
  NodeFields velocity(lattice, 0.0, false);
  double fastest = 0.0;
  for (std::int64_t i = 0; i < velocity.size(); ++i) {
    const Eigen::Vector3d x = lattice.position(Location::Node, i) - Eigen::Vector3d::Constant(0.5);
    const Eigen::Vector3d u(-x.y() + 0.3, x.x() + 0.2 * x.z(), 0.5 * x.y() - 0.1);
    for (int a = 0; a < 3; ++a) velocity.velocity(a)[i] = 2.0 * u[a];
    fastest = std::max(fastest, 2.0 * u.norm());
  }
  const double dt = 0.9 * dx / fastest;
  for (const bool maccormack : {false, true}) {
    LevelSetAdvector advector(lattice, maccormack);
    std::vector<double> everywhere(phi.size()), banded(phi.size());
    std::vector<std::int64_t> invalid;
    advector.advect(phi, velocity, dt, ShellGeometry(), nullptr, everywhere, invalid);
    advector.advect(phi, velocity, dt, ShellGeometry(), nullptr, banded, invalid, nullptr,
                    fastest * dt + 2.5 * dx);
    EXPECT_TRUE(invalid.empty());
    // Not vacuous: thousands of cells the band kept would have been traced to another φ.
    int differ = 0;
    for (size_t i = 0; i < phi.size(); ++i) differ += banded[i] != everywhere[i] ? 1 : 0;
    EXPECT_GT(differ, 1000) << maccormack;
    FastMarching fmm(lattice);
    fmm.reinitialize(everywhere, level_set.band(), ShellGeometry(), nullptr);
    fmm.reinitialize(banded, level_set.band(), ShellGeometry(), nullptr);
    EXPECT_EQ(banded, everywhere) << (maccormack ? "MacCormack" : "trilinear");
  }
}

TEST(FastMarching, ReinitialisesAStretchedSphereToItsDistance) {
  // φ = 3 (|x − c| − r): the zero set is the sphere; after fast marching φ must be the
  // signed distance within first-order accuracy (Sethian 1996: O(Δx); 0.6Δx bound from
  // the interface initialisation's error on a curved surface at r = 5Δx).
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 24, Eigen::Vector3i(24, 24, 24));
  const Eigen::Vector3d c(0.5, 0.5, 0.5);
  const double r = 0.21;
  std::vector<double> phi(grid.size(Location::Node));
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i)
    phi[i] = 3.0 * ((grid.position(Location::Node, i) - c).norm() - r);
  FastMarching fmm(grid);
  const double band = 5.0 * grid.dx();
  const auto stats = fmm.reinitialize(phi, band, ShellGeometry(), nullptr);
  EXPECT_GT(stats.interface_nodes, 0);
  double worst = 0.0;
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    const double exact = (grid.position(Location::Node, i) - c).norm() - r;
    if (std::abs(exact) < band - grid.dx()) worst = std::max(worst, std::abs(phi[i] - exact));
    EXPECT_LE(std::abs(phi[i]), band + 1e-12);
    EXPECT_EQ(phi[i] <= 0.0, exact <= 0.0 || std::abs(exact) < 1e-12);
  }
  EXPECT_LT(worst, 0.6 * grid.dx());
}

TEST(FastMarching, RepeatedReinitialisationKeepsASphere) {
  // A signed distance is a fixed point of reinitialisation: run 200 times (a second of
  // water at 200 steps per second), a sphere of r = 5.3Δx must keep its radius. Measured
  // on this sphere: the axis-crossing plane 1/sqrt(Σ 1/d_a^2) at the interface nodes
  // with a first-order march moved the surface 0.22Δx inwards (-11% of the volume; -0.4%
  // of a 3D dam break's water every step); |φ|/|∇φ| with central differences and the
  // second-order march, 0.021Δx outwards; with |∇φ| within 5% of 1 left alone, 0.0000Δx
  // (+0.01% of the volume). Bounds: 0.005Δx on the interface nodes' mean error (a quarter
  // of the undamped |φ|/|∇φ| drift) and 0.5% of the volume.
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 24, Eigen::Vector3i(24, 24, 24));
  const double dx = grid.dx();
  const Eigen::Vector3d c(0.5 + 0.31 * dx, 0.5 - 0.17 * dx, 0.5 + 0.07 * dx);  // off the nodes
  const double r = 5.3 * dx;
  LevelSet level_set(grid, 6.0 * dx);
  const grid::UniformGrid& lattice = level_set.grid();  // the cell centres
  auto& phi = level_set.phi();
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i)
    phi[i] = std::clamp((lattice.position(Location::Node, i) - c).norm() - r, -6.0 * dx, 6.0 * dx);
  const double v0 = level_set.volume();
  FastMarching fmm(lattice);
  for (int pass = 0; pass < 200; ++pass)
    fmm.reinitialize(phi, level_set.band(), ShellGeometry(), nullptr);
  EXPECT_NEAR(level_set.volume(), v0, 5e-3 * v0);
  // Mean radius of the zero set: the interface nodes (within Δx/2 of it, so each has an
  // axis neighbour across it), each moved by its φ.
  double drift = 0.0;
  int nodes = 0;
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    const double exact = (lattice.position(Location::Node, i) - c).norm() - r;
    if (std::abs(exact) > 0.5 * dx) continue;
    drift += phi[i] - exact;
    ++nodes;
  }
  ASSERT_GT(nodes, 0);
  std::printf("[  figure  ] drift %.4f dx volume %+.2f%%\n", drift / nodes / dx,
              100.0 * (level_set.volume() / v0 - 1.0));
  EXPECT_LT(std::abs(drift / nodes), 5e-3 * dx);
}

/// A box of water collapsing in a narrow tank (0.344 x 0.5 x 0.344 m at `resolution` cells
/// up, the box 0.05-0.29 m across, 0.19 m high) for `duration` s on `core`
/// (test::water_core's) with φ advected by `advection`: the largest |V/V0 − 1| after any step.
double collapsing_box_worst_change(int resolution, const char* core, const char* advection,
                                   double duration) {
  auto fluid = test::make_fluid(
      {{"domain", {{"min", {0.0, 0.0, 0.0}}, {"max", {0.34375, 0.5, 0.34375}}}},
       {"resolution", resolution},
       {"pressure", {{"tolerance", 1e-6}}},
       {"water",
        test::water_core(
            core,
            {{"advection", advection},
             {"initial",
              {{{"type", "box"}, {"min", {0.05, 0.0, 0.05}}, {"max", {0.29, 0.19, 0.29}}}}}})}});
  const double v0 = test::reported(*fluid, "water_volume");
  double worst = 0.0;
  test::run_between(*fluid, 0.0, duration, [&] {
    worst = std::max(worst, std::abs(test::reported(*fluid, "water_volume") / v0 - 1.0));
  });
  return worst;
}

TEST(LevelSetAdvection, ABoxCollapsingInANarrowTankKeepsItsWater) {
  // 24 cells up (16.5 across), 0.6 s: the box falls, runs up all four walls and back in
  // sheets a cell or two thick. The trilinear step alone: its wall cells hold the sheets,
  // bound 12 % of the water, set a quarter above the swing measured in docs/measured-figures.md
  // so that a step that loses more fails. With the volume fraction
  // (the default) the volume is F's on either φ step and changes only by what F's bounds
  // clip (MacCormack's sharper φ, whose planes F follows, clips most): bound 1e-4.
  // MacCormack's step alone loses more than the trilinear one here (a known limit,
  // docs/known-limits.md): printed, not asserted. Figures: docs/measured-figures.md.
  const double trilinear = collapsing_box_worst_change(24, "cells", "semi_lagrangian", 0.6);
  const double maccormack = collapsing_box_worst_change(24, "cells", "maccormack", 0.6);
  const double fraction = collapsing_box_worst_change(24, "fraction", "semi_lagrangian", 0.6);
  const double fraction_maccormack = collapsing_box_worst_change(24, "fraction", "maccormack", 0.6);
  std::printf(
      "[  figure  ] box collapsing in a narrow tank, 24 cells up, 0.6 s, largest |volume "
      "change|: level set alone %.2f%% trilinear, %.2f%% MacCormack; with F %.1e, %.1e\n",
      100.0 * trilinear, 100.0 * maccormack, fraction, fraction_maccormack);
  EXPECT_LT(trilinear, 0.12);
  EXPECT_LT(fraction, 1e-4);
  EXPECT_LT(fraction_maccormack, 1e-4);
}

/// One static shell as a fast-marching test hands it over: its geometry (ε = 1e-3 Δx,
/// the PhysBAM default) and its band (2Δx).
struct StaticShell {
  StaticShell(const grid::UniformGrid& grid, sdk::ShellSurface shell)
      : shells{std::move(shell)}, geometry(shells, 1e-3 * grid.dx()), band(grid) {
    band.add(geometry::TriangleMesh(shells.front()), 2.0 * grid.dx());
  }
  std::vector<sdk::ShellSurface> shells;
  ShellGeometry geometry;
  geometry::ShellBand band;
};

TEST(FastMarching, NeverMarchesAcrossAShell) {
  // Water in x < 0.3; a plate at x = 0.5 + Δx/3 with a dry side beyond it (φ = the band,
  // as a dry side holds). No distance may come from the water through the plate: nodes
  // beyond it keep the full band.
  const grid::UniformGrid mac(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(16, 16, 16));
  const grid::UniformGrid grid = LevelSet::cell_centre_lattice(mac);
  const double plate_x = 0.5 + grid.dx() / 3.0;
  const double width = 8.0 * grid.dx();
  std::vector<double> phi(grid.size(Location::Node));
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    const double x = grid.position(Location::Node, i).x();
    phi[i] = x > plate_x ? width : x - 0.3;
  }
  const StaticShell plate(mac, dam_plate(plate_x));
  FastMarching fmm(grid);
  fmm.reinitialize(phi, width, plate.geometry, &plate.band);
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    const double x = grid.position(Location::Node, i).x();
    if (x > plate_x) {
      EXPECT_DOUBLE_EQ(phi[i], width) << "node at x = " << x;
    } else if (x < 0.45) {
      // Plane distance, exact for first-order marching along an axis (round-off bound).
      EXPECT_NEAR(phi[i], x - 0.3, 1e-12) << "node at x = " << x;
    }
  }
}

TEST(FastMarching, KeepsAStillSurfaceThatAShellPiercesUnchanged) {
  // A level surface's signed distance is a fixed point of first-order fast marching (the
  // crossing along the vertical is exact, and so is the march along it). A tilted plate
  // through the surface hides some of those crossings; held nodes keep the plane there,
  // so the whole band stays the plane's distance up to round-off. The paper's rule,
  // min(distance to the shell, |φ|) against the shell, moves it by up to a cell.
  const grid::UniformGrid mac(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(16, 16, 16));
  const grid::UniformGrid grid = LevelSet::cell_centre_lattice(mac);
  const Eigen::Vector3d n = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d on_plane(0.5, 0.41, 0.5);
  const double width = 6.0 * grid.dx();
  std::vector<double> phi(grid.size(Location::Node));
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i)
    phi[i] = std::clamp(n.dot(grid.position(Location::Node, i) - on_plane), -width, width);
  const auto exact = phi;
  const StaticShell plate(
      mac,
      test::make_plate({0.5, 0.45, 0.52}, Eigen::Vector3d(1.0, 0.3, -0.4).normalized(), 0.6, 7));
  FastMarching fmm(grid);
  fmm.reinitialize(phi, width, plate.geometry, &plate.band);
  int near_plate = 0;
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    if (std::abs(exact[i]) < width - grid.dx()) {
      EXPECT_NEAR(phi[i], exact[i], 1e-12) << i;
    }
    near_plate += std::abs(exact[i]) < grid.dx() && plate.band.contains(Location::Cell, i) ? 1 : 0;
  }
  EXPECT_GT(near_plate, 10);  // the plate does cross the surface's cells
}

}  // namespace
}  // namespace shellflow::grid_fluid
