// Water thinner than a cell on a shell (§4.4, §4.4.1; Guendelman et al. 2005): such a film
// has no wet node on its side, only dry nodes that hold less than their distance to the
// shell. Whoever reads φ across the shell must continue the reader's side linearly (the
// other side's nodes say nothing of it): the advection's and the particles' samples, the
// pressure's cell classification and the volume measure.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "grid_fluid_test_support.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/grid_fluid/water/level_set_advector.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

/// Twenty degrees off level about a skew axis: the plate meets no plane of nodes square.
const Eigen::Vector3d kTiltAxis = Eigen::Vector3d(-0.3, 0.0, -1.0).normalized();
constexpr double kTiltDeg = 20.0;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

Eigen::Matrix3d tilt() {
  return Eigen::AngleAxisd(kTiltDeg * std::numbers::pi / 180.0, kTiltAxis).toRotationMatrix();
}

TEST(ShellFilm, AFilmsLinearWaterIsReadExactlyFromEitherSideOfAShell) {
  // φ linear, its surface parallel to a skew-tilted plate and 0.37Δx off it, water towards
  // the plate (a film on it, on whichever side samples): trilinear interpolation is exact,
  // and so must the sample be when the corners across the plate are continued from the
  // sample's side. There the linear continuation is the wetter one, and it is exact;
  // constant continuation reads the film's dry nodes as the water's and is off by up to
  // about a cell. Each side is continued from its own nodes only: with the other side's
  // nodes set to nonsense the samples must not change.
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(16, 16, 16));
  const double dx = grid.dx();
  const Eigen::Vector3d c(0.5, 0.5 + 0.3 * dx, 0.5);
  const Eigen::Vector3d n = tilt() * Eigen::Vector3d::UnitY();
  const sdk::ShellSurface plate = test::make_plate(c, n, 1.4, 15);
  const std::vector<sdk::ShellSurface> shells{plate};
  const ShellGeometry geometry(shells, 1e-3 * dx);
  std::vector<double> phi(grid.size(Location::Node)), scrambled(phi.size());
  LevelSetAdvector sampler(grid);
  for (const double side : {1.0, -1.0}) {
    const auto linear = [&](const Eigen::Vector3d& x) { return side * n.dot(x - c) - 0.37 * dx; };
    for (std::int64_t i = 0; i < grid.size(Location::Node); ++i) {
      const Eigen::Vector3d x = grid.position(Location::Node, i);
      phi[i] = linear(x);
      scrambled[i] = side * n.dot(x - c) < 0.0 ? 7.0 * dx : phi[i];  // the other side
    }
    int across = 0;
    double worst_constant = 0.0;  // how much drier constant continuation reads the film
    for (int s = 0; s < 400; ++s) {
      // Points within 0.8Δx of the plate on this side, spread over its middle.
      const double u = 0.3 * std::sin(1.7 * s), v = 0.3 * std::cos(2.3 * s + 0.4);
      const double h = side * (0.05 + 0.75 * std::abs(std::sin(0.9 * s + 1.1))) * dx;
      const Eigen::Vector3d p = c + tilt() * Eigen::Vector3d(u, 0.0, v) + h * n;
      const auto value = sampler.sample_visible(scrambled, p, geometry);
      ASSERT_TRUE(value.has_value()) << p.transpose();
      // Round-off of a few sums of O(1) values.
      EXPECT_NEAR(*value, linear(p), 1e-12) << "side " << side << " at " << p.transpose();
      const auto constant = sampler.sample_visible(scrambled, p, geometry, nullptr, false);
      worst_constant = std::max(worst_constant, *constant - linear(p));
      // Not vacuous: the sample's cell reaches across the plate.
      const NodeStencil st = node_stencil(grid, p);
      for (int k = 0; k < 8; ++k)
        if (!geometry.visible(p, grid.position(Location::Node, st.corner(grid, k)))) {
          ++across;
          break;
        }
    }
    EXPECT_GT(across, 200) << "side " << side;
    EXPECT_GT(worst_constant, 0.1 * dx) << "side " << side;
  }
}

/// The advection tests' tank and plate: 16³, a skew-tilted plate through c (0.3Δx above a
/// node plane), a step of 0.4Δx s (up to a cell at the speeds used), and the plate's two
/// velocities: static, and moving off the film's side at 0.3 m/s and along it.
struct TiltedPlate {
  grid::UniformGrid mac{Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(16, 16, 16)};
  grid::UniformGrid grid = LevelSet::cell_centre_lattice(mac);  ///< φ's samples
  double dx = grid.dx();
  Eigen::Vector3d c{0.5, 0.5 + 0.3 * dx, 0.5};
  Eigen::Vector3d n = tilt() * Eigen::Vector3d::UnitY();
  Eigen::Vector3d along = tilt() * Eigen::Vector3d(1.0, 0.0, 0.4).normalized();
  double dt = 0.4 * dx;
  std::array<Eigen::Vector3d, 2> plate_velocities{Eigen::Vector3d::Zero(), -0.3 * n + 0.2 * along};

  /// x's signed distance from the plate at rest, + on the film's side.
  double off_plate(const Eigen::Vector3d& x) const { return n.dot(x - c); }
  /// Two cells or more from the tank's walls (nearer, a path back is cut at the wall).
  bool away_from_walls(const Eigen::Vector3d& x) const {
    return (x.array() >= 2.0 * dx).all() && (x.array() <= 1.0 - 2.0 * dx).all();
  }
  /// A film's linear φ, its surface parallel to the plate 0.37Δx off it, water towards the
  /// plate, after `time` of moving with the plate at `velocity`.
  double film(const Eigen::Vector3d& x, const Eigen::Vector3d& velocity, double time) const {
    return off_plate(x - time * velocity) - 0.37 * dx;
  }
  /// f at every node.
  template <class F>
  std::vector<double> on_nodes(F f) const {
    std::vector<double> v(grid.size(Location::Node));
    for (std::int64_t i = 0; i < grid.size(Location::Node); ++i)
      v[i] = f(grid.position(Location::Node, i));
    return v;
  }
};

/// That plate moving at `velocity`: its geometry, its 3Δx band, and node velocities u
/// throughout.
struct MovingPlate {
  MovingPlate(const TiltedPlate& tank, const Eigen::Vector3d& velocity, const Eigen::Vector3d& u)
      : shells{moving(tank, velocity)},
        geometry(shells, 1e-3 * tank.dx),
        band(tank.mac),
        nodes(tank.grid, 0.0, false) {
    band.add(geometry::TriangleMesh(shells.front()), 3.0 * tank.dx);
    for (int a = 0; a < 3; ++a) std::fill(nodes.velocity(a).begin(), nodes.velocity(a).end(), u[a]);
  }
  static sdk::ShellSurface moving(const TiltedPlate& tank, const Eigen::Vector3d& velocity) {
    sdk::ShellSurface plate = test::make_plate(tank.c, tank.n, 1.4, 15);
    plate.velocities.rowwise() = velocity.transpose();
    return plate;
  }
  std::vector<sdk::ShellSurface> shells;
  ShellGeometry geometry;
  geometry::ShellBand band;
  NodeFields nodes;
};

TEST(ShellFilm, APathBackIntoTheShellSlidesAlongItAndKeepsTheFilm) {
  // A film's linear φ (surface parallel to a skew-tilted plate, 0.37Δx off it, water on the
  // plate) carried by node velocities along the plate plus a part off it, as the nodes
  // next to a shell get from the faces it closes per axis. The water does not leave the
  // plate, so a node whose path back would cross the plate reads φ where the path slides
  // along it, with the plate's own normal motion: the film moved with the plate, exact for
  // a linear φ (to round-off). Stopped at the plate (the constant continuation there), it
  // read the film's dry nodes, more than 0.1Δx too dry: the test asserts that too, so it is
  // not vacuous. Static, and moving off the film's side at 0.3 m/s and along it.
  const TiltedPlate tank;
  const grid::UniformGrid& grid = tank.grid;
  for (const Eigen::Vector3d& plate_velocity : tank.plate_velocities) {
    // The film at n, and where it is at n+1, moved with the plate.
    const auto film = [&](const Eigen::Vector3d& x, double time) {
      return tank.film(x, plate_velocity, time);
    };
    const Eigen::Vector3d u = plate_velocity + 0.5 * tank.along + 1.5 * tank.n;  // off the plate
    const MovingPlate scene(tank, plate_velocity, u);
    const ShellGeometry& geometry = scene.geometry;
    const std::vector<double> phi =
        tank.on_nodes([&](const Eigen::Vector3d& x) { return film(x, 0.0); });
    std::vector<double> out(phi.size());
    LevelSetAdvector advector(grid);
    std::vector<std::int64_t> invalid;
    advector.advect(phi, scene.nodes, tank.dt, geometry, &scene.band, out, invalid);
    int slid = 0;
    double worst_clipped = 0.0;  // how much drier the path stopped at the plate reads
    for (std::int64_t i = 0; i < grid.size(Location::Node); ++i) {
      const Eigen::Vector3d x = grid.position(Location::Node, i);
      const Eigen::Vector3d back = x - tank.dt * u;
      // On the water side, away from the tank's walls, outside the plate's wedge (§4.1: a
      // node in it has no side to slide on).
      if (!tank.away_from_walls(x) || tank.off_plate(x) <= 0.01 * tank.dx ||
          !geometry.first_hit(x, back))
        continue;
      ++slid;
      // Round-off of a few sums of O(1) values.
      EXPECT_NEAR(out[i], film(x, tank.dt), 1e-12) << "node " << x.transpose();
      const Eigen::Vector3d stopped =
          geometry.clip(x, back, geometry::WedgeCaster::kSemiLagrangianFactor * geometry.epsilon());
      worst_clipped =
          std::max(worst_clipped, *advector.sample_visible(phi, stopped, geometry, nullptr, false) -
                                      film(stopped, 0.0));
    }
    EXPECT_TRUE(invalid.empty());
    EXPECT_GT(slid, 40) << "plate velocity " << plate_velocity.transpose();
    EXPECT_GT(worst_clipped, 0.1 * tank.dx) << "plate velocity " << plate_velocity.transpose();
  }
}

TEST(ShellFilm, AirAboveAFilmIsNotTracedOntoItWhileWaterComingAtTheShellArrives) {
  // Node velocities onto a skew-tilted plate (as extrapolation from thicker water gives the
  // air above a film), static and with the plate moving. Over a film 0.37Δx thick (its
  // surface parallel to the plate, φ rising off it) the air nodes within Δx of the plate
  // trace without that normal part relative to the plate: the film moves with the plate,
  // exact for a linear φ (to round-off); with it, each would read the air Δt|u_n| further
  // off, drier by more than 0.1Δx (asserted too, so the test is not vacuous). Water
  // beyond an air gap instead (φ falling off the plate: a layer 1.2Δx off it) comes at the
  // plate: those nodes trace with the whole velocity.
  const TiltedPlate tank;
  const grid::UniformGrid& grid = tank.grid;
  const double dx = tank.dx, dt = tank.dt;
  for (const Eigen::Vector3d& plate_velocity : tank.plate_velocities) {
    const Eigen::Vector3d u = plate_velocity + 0.5 * tank.along - 1.5 * tank.n;  // onto the plate
    const MovingPlate scene(tank, plate_velocity, u);
    const ShellGeometry& geometry = scene.geometry;
    // On the plate's +n side, away from the tank's walls, outside its wedge, within Δx.
    const auto near_plate = [&](const Eigen::Vector3d& x) {
      const double off = tank.off_plate(x);
      return tank.away_from_walls(x) && off > 0.01 * dx && off < dx;
    };
    LevelSetAdvector advector(grid);
    std::vector<double> out(grid.size(Location::Node));
    std::vector<std::int64_t> invalid;
    {
      const auto film = [&](const Eigen::Vector3d& x, double time) {
        return tank.film(x, plate_velocity, time);
      };
      const std::vector<double> phi =
          tank.on_nodes([&](const Eigen::Vector3d& x) { return film(x, 0.0); });
      advector.advect(phi, scene.nodes, dt, geometry, &scene.band, out, invalid);
      int checked = 0;
      double worst_traced = 0.0;  // how much drier the whole velocity's trace reads
      for (std::int64_t i = 0; i < grid.size(Location::Node); ++i) {
        const Eigen::Vector3d x = grid.position(Location::Node, i);
        if (!near_plate(x) || phi[i] <= 0.0) continue;
        ++checked;
        // Round-off of a few sums of O(1) values.
        EXPECT_NEAR(out[i], film(x, dt), 1e-12) << "node " << x.transpose();
        worst_traced = std::max(worst_traced, film(x - dt * u, 0.0) - film(x, dt));
      }
      EXPECT_GT(checked, 40) << "plate velocity " << plate_velocity.transpose();
      EXPECT_GT(worst_traced, 0.1 * dx) << "plate velocity " << plate_velocity.transpose();
    }
    {
      // A layer 1.2Δx off the plate, air between.
      const std::vector<double> phi =
          tank.on_nodes([&](const Eigen::Vector3d& x) { return 1.2 * dx - tank.off_plate(x); });
      advector.advect(phi, scene.nodes, dt, geometry, &scene.band, out, invalid);
      int checked = 0;
      for (std::int64_t i = 0; i < grid.size(Location::Node); ++i) {
        const Eigen::Vector3d x = grid.position(Location::Node, i);
        if (!near_plate(x)) continue;
        ++checked;
        // Where the whole velocity's path back ends, read as every trace reads (the cell
        // there may reach across the plate).
        EXPECT_NEAR(out[i], *advector.sample_visible(phi, x - dt * u, geometry), 1e-12)
            << "node " << x.transpose();
      }
      EXPECT_GT(checked, 40) << "plate velocity " << plate_velocity.transpose();
    }
    EXPECT_TRUE(invalid.empty());
  }
}

TEST(ShellFilm, TwoSidedCellFractionTilesTheCellAndCutsItAtThePlane) {
  // (1) With the same φ on both sides the plane only splits the six tetrahedra into
  // pieces, so any plane must give the one-φ fraction. (2) All water on one side and all
  // air on the other gives the volume of the cell on that side of the plane (the
  // half-space's inclusion–exclusion, as water_test's flat-surface case). Round-off: 1e-13.
  const std::array<Eigen::Vector3d, 3> planes = {Eigen::Vector3d(0.3, 0.9, 0.2),
                                                 Eigen::Vector3d(-0.7, 0.1, 0.5),
                                                 Eigen::Vector3d(0.05, -0.4, -0.9)};
  for (const Eigen::Vector3d& direction : planes)
    for (const double offset : {-0.21, 0.0, 0.137}) {
      const Eigen::Vector3d m = direction.normalized();
      const double e = m.dot(Eigen::Vector3d::Constant(0.5)) + offset;
      std::array<double, 8> side, phi, water, air;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d x(k & 1, (k >> 1) & 1, k >> 2);
        side[k] = m.dot(x) - e;
        phi[k] = Eigen::Vector3d(0.6, -0.2, 0.75).normalized().dot(x) - 0.55;
        water[k] = -1.0;
        air[k] = 1.0;
      }
      EXPECT_NEAR(LevelSet::two_sided_cell_fraction(phi, phi, side), LevelSet::cell_fraction(phi),
                  1e-13);
      // Water below the plane: the half-space m·x < e of the unit cube.
      double below = 0.0;
      {
        // Inclusion–exclusion of the corner simplices (every component of m is nonzero).
        Eigen::Vector3d mm = m;
        double dd = e;
        for (int a = 0; a < 3; ++a)
          if (mm[a] < 0.0) dd -= mm[a], mm[a] = -mm[a];
        for (int k = 0; k < 8; ++k) {
          const Eigen::Vector3d v(k & 1, (k >> 1) & 1, k >> 2);
          const double reach = std::max(0.0, dd - mm.dot(v));
          below += ((k & 1) + ((k >> 1) & 1) + (k >> 2)) % 2 ? -reach * reach * reach
                                                             : reach * reach * reach;
        }
        below /= 6.0 * mm.x() * mm.y() * mm.z();
      }
      EXPECT_NEAR(LevelSet::two_sided_cell_fraction(water, air, side), below, 1e-13);
      EXPECT_NEAR(LevelSet::two_sided_cell_fraction(air, water, side), 1.0 - below, 1e-13);
      EXPECT_GT(below, 0.05);  // not vacuous: the plane cuts the cell
      EXPECT_LT(below, 0.95);
    }
}

struct FilmRun {
  double start = 0.0;  ///< water_volume at the start of the first step, over the film's
  double kept = 0.0;   ///< water_volume after the turn, over the film's
};

/// A film `thickness` [Δx] thick, 0.3 m square, lying on a static tilted plate through
/// the tank's centre, carried a quarter of the way round by a prescribed rigid turn about
/// the plate's normal, with `per_cell` particles per cell.
FilmRun film_run(int cells, double thickness, int per_cell) {
  const double dx = 1.0 / cells;
  const Eigen::Vector3d c(0.5, 0.5 + 0.3 * dx, 0.5);
  const Eigen::Vector3d n = tilt() * Eigen::Vector3d::UnitY();
  const double period = 4.0;
  auto fluid = test::make_fluid(
      {{"resolution", cells},
       {"water", test::water_core("cells", {{"particles", {{"per_cell", per_cell}}}})},
       {"prescribed_velocity",
        {{"type", "rigid_rotation"},
         {"center", {c.x(), c.y(), c.z()}},
         {"axis", {n.x(), n.y(), n.z()}},
         {"period", period}}}},
      Eigen::Vector3d::Zero());
  // The film's exact signed distance on its side of the plate: a box 0.3 × t × 0.3 in the
  // plate's frame, 0.2 m from the turn's axis, its underside on the plate (so that side's φ
  // is the distance to its top and edges, continuing through the plate); beneath the plate
  // the distance to the box. (A scene's initial water is made a distance without the
  // shells, which no film thinner than a cell survives.)
  const double top = thickness * dx;
  const grid::UniformGrid& grid = fluid->liquid()->level_set().grid();
  auto& phi = fluid->liquid()->level_set().phi();
  for (std::int64_t i = 0; i < grid.size(Location::Node); ++i) {
    const Eigen::Vector3d l = tilt().transpose() * (grid.position(Location::Node, i) - c);
    const double beneath = l.y() < 0.0 ? std::abs(l.y()) : -kInfinity;  // underside
    const Eigen::Vector3d q(std::abs(l.x() - 0.2) - 0.15, std::max(l.y() - top, beneath),
                            std::abs(l.z()) - 0.15);
    phi[i] = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  const sdk::ShellSurface plate = test::make_plate(c, n, 1.4, 15);
  const std::vector<sdk::ShellSurface> shells{plate};
  const std::vector<sdk::Positions> v_eff{plate.velocities};
  const double v0 = 0.3 * 0.3 * top;
  fluid->liquid()->particles().seed(fluid->liquid()->level_set(), ShellGeometry(shells, 1e-3 * dx));
  test::run_for(*fluid, 0.25 * period, shells, v_eff);
  return {fluid->liquid()->initial_volume() / v0, test::reported(*fluid, "water_volume") / v0};
}

TEST(ShellFilmSlow, FilmThinnerThanACellKeepsItsWaterWhileCarriedAlongATiltedPlate) {
  // The flow turns the film within the plate's plane, so the known answer is no change
  // of volume. A film 0.6Δx thick has no wet node; read across the plate with constant
  // continuation (its dry nodes' φ taken for the water's, as before linear continuation)
  // it was gone within the turn, with particles or without (0.0% kept both ways).
  // Measured now: 40% kept by the level set alone, which rounds the film's rim every step,
  // and 80% with 16 particles per cell, which lose most of the rest in the first 0.3 s.
  // Bounds: 25% and 60%, below the figures for films 0.3–1Δx thick (29–43%, 67–82%).
  const FilmRun alone = film_run(32, 0.6, 0);
  const FilmRun particles = film_run(32, 0.6, 16);
  std::printf(
      "[  figure  ] film 0.6 dx thick on a tilted plate, quarter turn at 32^3: %.1f%% "
      "kept alone, %.1f%% with 16 particles per cell; read at the start %.1f%%\n",
      100.0 * alone.kept, 100.0 * particles.kept, 100.0 * alone.start);
  EXPECT_GT(alone.kept, 0.25);
  EXPECT_GT(particles.kept, 0.6);
  EXPECT_LT(particles.kept, 1.05);  // and no water made
  // The measure reads the film at the start: the rim's sharp rounding, O(Δx/0.3 m) of it.
  EXPECT_NEAR(alone.start, 1.0, 0.05);
}

/// A 1 × 0.5 × 0.25 m tank at 32 cells with a shelf spanning it a third of a cell above a
/// node plane (y = kShelf, air sealed beneath) and a layer `layer`Δx thick on it; the
/// projection to 1e-6.
TEST(ShellFilm, AFaceCutByAShellPassesThePartOfItsSquareOnItsCentresSide) {
  // The pressure solves' face fraction (Batty et al. 2007): the area of the face's square on
  // its centre's side of a plane, against a count of 400 × 400 midpoints (which errs by at
  // most the cells the trace crosses, 2 × 400 of 400², 5e-3), and known values.
  EXPECT_DOUBLE_EQ(open_square_fraction(0.0, 0.0, 0.3), 1.0);     // parallel to the face
  EXPECT_NEAR(open_square_fraction(1.0, 0.0, 0.2), 0.7, 1e-14);   // ½ + h
  EXPECT_NEAR(open_square_fraction(0.0, -1.0, 0.5), 1.0, 1e-14);  // along its edge
  EXPECT_NEAR(open_square_fraction(std::sqrt(0.5), std::sqrt(0.5), 0.0), 0.5, 1e-14);
  for (int k = 0; k < 40; ++k) {
    const double angle = 0.37 + 1.91 * k, offset = 0.75 * std::abs(std::sin(2.3 * k + 0.2));
    const double m1 = std::cos(angle), m2 = std::sin(angle);
    int inside = 0;
    constexpr int n = 400;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        inside += m1 * ((i + 0.5) / n - 0.5) + m2 * ((j + 0.5) / n - 0.5) + offset >= 0.0;
    EXPECT_NEAR(open_square_fraction(m1, m2, offset), double(inside) / (n * n), 5e-3)
        << "m = (" << m1 << ", " << m2 << "), offset " << offset;
  }
  // A level plate a third of a cell above a plane of nodes (16 cells): the x and z faces of
  // the cells it cuts, whose centres lie half a cell up, keep ½ + 1/6 of their squares; the
  // y faces parallel it, and no other face reaches it.
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(16, 16, 16));
  const double dx = grid.dx(), y = 7.0 * dx + dx / 3.0;
  const std::vector<sdk::ShellSurface> shells{
      test::make_plate({0.5, y, 0.5}, Eigen::Vector3d::UnitY(), 0.6, 9)};
  const ShellGeometry geometry(shells, 1e-3 * dx);
  geometry::ShellBand band(grid);
  band.add(geometry::TriangleMesh(shells.front()), 2.0 * dx);
  const auto& apertures = geometry.face_apertures(band);
  EXPECT_TRUE(apertures[1].empty());
  for (const int a : {0, 2}) {
    const grid::Location loc = a == 0 ? Location::FaceX : Location::FaceZ;
    for (const FaceAperture& open : apertures[a]) {
      EXPECT_EQ(grid.coordinates(loc, open.face).y(), 7) << "axis " << a;
      EXPECT_NEAR(open.fraction, 0.5 + 1.0 / 6.0, 1e-12) << "axis " << a;
    }
    // Every face of row 7 under the plate (it spans 0.2 … 0.8), a cell in from its edges,
    // is there.
    int expected = 0, inner = 0;
    const Eigen::Vector3i counts = grid.counts(loc);
    for (int k = 0; k < counts.z(); ++k)
      for (int i = 0; i < counts.x(); ++i) {
        const Eigen::Vector3d p = grid.position(loc, Eigen::Vector3i(i, 7, k));
        if (i == 0 || k == 0 || i == counts.x() - 1 || k == counts.z() - 1) continue;
        expected += std::abs(p.x() - 0.5) < 0.3 - dx && std::abs(p.z() - 0.5) < 0.3 - dx;
      }
    for (const FaceAperture& open : apertures[a]) {
      const Eigen::Vector3d p = grid.position(loc, open.face);
      inner += std::abs(p.x() - 0.5) < 0.3 - dx && std::abs(p.z() - 0.5) < 0.3 - dx;
    }
    EXPECT_GT(expected, 50);
    EXPECT_EQ(inner, expected) << "axis " << a;
  }
}

/// A column of water 0.25 m wide and 0.5 m high against the left wall of a tank 1 m wide at
/// 32 cells, four cells deep, let go on a shelf spanning the tank a fraction `above` of a
/// cell above a plane of nodes (air beneath it), or on the tank's floor (`above` < 0); the
/// relative change of its volume after 0.33 s, before its front reaches the far wall.
double column_collapsing_on_a_shelf(double above) {
  // The tank's floor lies 8 cells below the shelf's plane of nodes, or is the floor itself.
  const double dx = 1.0 / 32.0, floor = 0.25 + (above < 0.0 ? 0.0 : above * dx);
  const double bottom = above < 0.0 ? floor : 0.0;
  auto fluid = test::make_fluid(
      {{"domain", {{"min", {0.0, bottom, 0.0}}, {"max", {1.0, bottom + 1.0, 4 * dx}}}},
       {"resolution", 32},
       {"water",
        {{"initial",
          {{{"type", "box"}, {"min", {-1, floor, -1}}, {"max", {0.25, floor + 0.5, 1}}}}}}}});
  std::vector<sdk::ShellSurface> shells;
  if (above >= 0.0)
    shells.push_back(test::make_plate({0.5, floor, 2 * dx}, Eigen::Vector3d::UnitY(), 1.1, 12));
  std::vector<sdk::Positions> v_eff;
  for (const auto& s : shells) v_eff.push_back(s.velocities);
  test::run_for(*fluid, 0.33, shells, v_eff);
  const double volume = test::reported(*fluid, "water_volume");
  const double change = test::reported(*fluid, "water_volume_change");
  return change / (volume - change);
}

TEST(ShellFilm, AColumnCollapsingOnAShelfBetweenNodePlanesKeepsItsWaterAsOnTheFloor) {
  // The collapsing column runs out along the shelf. The pressure solve took each cell the
  // shelf cuts as all water where its centre lies above the shelf, and let the water flow
  // into the part under it: the column sank into a shelf a third of a cell above a plane of
  // nodes (the cells' centres half a cell up) and lost 7.4 % in 0.33 s, 3.5 % a tenth of a
  // cell above, where on the tank's floor it loses 0.01 %. The faces of those cells now pass
  // only their part above the shelf (face fractions): measured −0.9 % and −1.7 %. The
  // bounds: those and half again; 0.3 % on the floor. Two thirds of a cell above the nodes,
  // over the cells' centres, the part of a cell above the shelf belongs to no cell of the
  // water's side and the column gains (measured +6.2 %, as before the fractions; README,
  // Known limits): bounded, as measured and half again, so that it does not grow unseen.
  const double floor = column_collapsing_on_a_shelf(-1.0);
  const double third = column_collapsing_on_a_shelf(1.0 / 3.0);
  const double tenth = column_collapsing_on_a_shelf(0.1);
  const double two_thirds = column_collapsing_on_a_shelf(2.0 / 3.0);
  std::printf(
      "[  figure  ] column collapsing, 0.33 s: volume %+.2f%% on the floor; on a shelf "
      "above a plane of nodes by a third of a cell %+.2f%%, a tenth %+.2f%%, two thirds "
      "%+.2f%%\n",
      100.0 * floor, 100.0 * third, 100.0 * tenth, 100.0 * two_thirds);
  EXPECT_LT(std::abs(floor), 0.003);
  EXPECT_LT(std::abs(third), 0.014);
  EXPECT_LT(std::abs(tenth), 0.025);
  EXPECT_LT(std::abs(two_thirds), 0.093);
}

constexpr double kShelfDx = 1.0 / 32.0, kShelf = 0.2104, kShelfArea = 1.0 * 0.25;
/// `core`: test::water_core's ("cells" or "fraction").
std::unique_ptr<GridFluid> layer_on_a_shelf(double layer, const char* core = "cells") {
  return test::make_fluid(
      {{"domain", {{"min", {0, 0, 0}}, {"max", {1.0, 0.5, 0.25}}}},
       {"resolution", 32},
       {"pressure", {{"tolerance", 1e-6}}},
       {"water", test::water_core(core, {{"initial",
                                          {{{"type", "box"},
                                            {"min", {-1, kShelf, -1}},
                                            {"max", {2, kShelf + layer * kShelfDx, 2}}}}}})}});
}

TEST(ShellFilm, AStillLayerOnAShelfKeepsItsWater) {
  // Water at rest in a layer on a shelf that spans a 1 × 0.5 × 0.25 m tank at 32 cells,
  // the shelf a third of a cell above a node plane (y = 0.2104), air sealed beneath. The
  // first nodes above the shelf hold (fast marching's rule next to a shell) their distance
  // to the shelf where it is nearer than the surface; their neighbours above took that for
  // the surface's slope, and every step lowered the surface: −4.2 / −19 / −45 % in 0.5 s
  // for layers 0.7 / 0.96 / 1.2Δx thick. And the first march, at construction, sees no
  // shell: it took the layer's underside on the shelf for a surface (−2.6 / −3.5 % more for
  // 0.96 / 1.2Δx). Still water is a fixed point of both now: the volume (each side of the
  // cut cells with its own level set) keeps within 1e-5 (measured 0, 0, −1.6e-7: what the
  // projection's tolerance of 1e-6 leaves of motion).
  for (const double layer : {0.7, 0.96, 1.2}) {
    auto fluid = layer_on_a_shelf(layer);
    const std::vector<sdk::ShellSurface> shells{
        test::make_plate({0.5, kShelf, 0.125}, Eigen::Vector3d::UnitY(), 1.2, 13)};
    const std::vector<sdk::Positions> v_eff{shells.front().velocities};
    test::run_for(*fluid, 0.5, shells, v_eff);
    const double volume = test::reported(*fluid, "water_volume");
    const double change = test::reported(*fluid, "water_volume_change");
    std::printf("[  figure  ] still layer %.2f dx on a shelf, 0.5 s: volume %+.2e of %.6f m^3\n",
                layer, change / (volume - change), volume - change);
    EXPECT_LE(std::abs(change), 1e-5 * (volume - change)) << layer;
  }
}

/// The largest |water_volume_change| [m^3] while a layer `layer`Δx thick rides the shelf,
/// carried at `speed` (m/s, along y) for `duration` from rest; the fluid is told the shelf's
/// motion before the first step (FluidSolver::start, §6).
double widest_change_carried(double layer, double speed, double duration,
                             const char* core = "fraction") {
  auto fluid = layer_on_a_shelf(layer, core);
  const auto shelf_at = [&](double t) {
    auto plate =
        test::make_plate({0.5, kShelf + speed * t, 0.125}, Eigen::Vector3d::UnitY(), 1.2, 13);
    plate.velocities.col(1).setConstant(speed);
    return std::vector<sdk::ShellSurface>{plate};
  };
  fluid->start(fluid->stable_dt(0.9), shelf_at(0.0),
               std::vector<sdk::Positions>{shelf_at(0.0).front().velocities});
  double t = 0.0, widest = 0.0;
  while (t < duration - 1e-12) {
    const double dt = std::min(fluid->stable_dt(0.9), duration - t);
    const auto n = shelf_at(t), np1 = shelf_at(t + dt);
    fluid->advect(t, dt, n, np1);
    fluid->project(dt, np1, std::vector<sdk::Positions>{np1.front().velocities});
    t += dt;
    widest = std::max(widest, std::abs(test::reported(*fluid, "water_volume_change")));
  }
  return widest;
}

TEST(ShellFilm, ALayerCarriedByAMovingShelfReadsTheSameVolumeWhereverTheShelfIs) {
  // A layer 2.5Δx thick on a shelf spanning the tank, the shelf carried up (and, in a second
  // run, down) at 0.3 m/s through three planes of nodes: the water moves with it, and the
  // volume that water_volume reports must not depend on where the shelf stands between the
  // planes of centres. It was read against the shells of the step before, a step behind
  // the water, and swung by 0.2 to 1.1Δx of layer as the shelf crossed them. The water
  // starts at rest on a shelf already moving: start() gives it the shelf's motion before
  // the first step (§6), without which the first step took (or left) V·Δt of layer
  // (0.32Δx), the water standing while the shelf moved on. With F the volume is Σ F:
  // round-off. Bound: 1e-6Δx of layer.
  for (const double speed : {0.3, -0.3}) {
    const double widest = widest_change_carried(2.5, speed, 0.3);
    std::printf(
        "[  figure  ] layer carried at %+.1f m/s through 3 planes of centres from rest: volume "
        "within %.1e dx of layer\n",
        speed, widest / (kShelfArea * kShelfDx));
    EXPECT_LE(widest, 1e-6 * kShelfArea * kShelfDx) << speed;
  }
}

TEST(ShellFilm, ALayerThinnerThanTwoCellsCarriedAcrossPlanesOfCentresKeepsItsWater) {
  // Layers 0.5 to 1.5Δx thick on the shelf, carried down (0.05 and 0.3 m/s) and up (0.3 m/s)
  // by 1.5Δx, across a plane of centres: the water moves with the shelf, and the volume must
  // stay. F carries the layer through the cells the shelf cuts (φ there is left to the level
  // set, its dilation weighted by F), and water_volume is Σ F: kept to round-off and what
  // F's lower bound raises (measured: 4.6e-9 of a cell's depth of layer at most). Bound: 1e-6
  // of it. (The level set alone loses up to 0.7Δx of layer here: docs/known-limits.md.)
  for (const double layer : {0.5, 0.8, 1.2, 1.5})
    for (const double speed : {-0.05, -0.3, 0.3}) {
      const double widest = widest_change_carried(layer, speed, 1.5 * kShelfDx / std::abs(speed));
      std::printf(
          "[  figure  ] layer %.1f dx carried %+.2f m/s across a plane of centres, with F: volume "
          "within %.1e dx of layer\n",
          layer, speed, widest / (kShelfArea * kShelfDx));
      EXPECT_LE(widest, 1e-6 * kShelfArea * kShelfDx) << layer << " dx at " << speed << " m/s";
    }
}

}  // namespace
}  // namespace shellflow::grid_fluid
