// Water carried by a prescribed analytic velocity ("prescribed_velocity"): the fields
// themselves (LeVeque's deformation is divergence-free and undoes itself at T, a rigid
// rotation turns once per period), the scene mode that imposes them (no solve, the field
// on the nodes and faces), Zalesak's slotted sphere built from the scene's "subtract", and
// the suite's small version of LeVeque's deformation test of the particle level set
// (Enright et al. 2002, §5.4; the 100^3 one is `shellflow bench
// configs/bench/leveque_deformation.json`).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "grid_fluid_test_support.hpp"
#include "shellflow/grid_fluid/mac/analytic_velocity.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/metrics.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

const grid::UniformGrid kUnitBox(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i::Constant(16));

AnalyticVelocity field(const nlohmann::json& params, const grid::UniformGrid& grid = kUnitBox) {
  nlohmann::json wrapped = {{"prescribed_velocity", params}, {"water", nlohmann::json::object()}};
  return AnalyticVelocity(test::validated(wrapped)["prescribed_velocity"], grid);
}

/// x(t1) from x(t0) along the field by classical RK4 in `steps` steps.
Eigen::Vector3d trace(const AnalyticVelocity& f, Eigen::Vector3d x, double t0, double t1,
                      int steps) {
  const double h = (t1 - t0) / steps;
  for (int s = 0; s < steps; ++s) {
    const double t = t0 + s * h;
    const Eigen::Vector3d k1 = f.velocity(x, t);
    const Eigen::Vector3d k2 = f.velocity(x + 0.5 * h * k1, t + 0.5 * h);
    const Eigen::Vector3d k3 = f.velocity(x + 0.5 * h * k2, t + 0.5 * h);
    const Eigen::Vector3d k4 = f.velocity(x + h * k3, t + h);
    x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return x;
}

TEST(AnalyticVelocity, DeformationIsDivergenceFreeAndHasNoFlowThroughTheWalls) {
  // A box that is not a cube (each component scaled by its side): central differences of
  // step h have error O(h²) ~ 1e-8 on derivatives of order 2π² L; 1e-6 bounds it. The
  // walls: sin(0) and sin(π) are 0 and 1.2e-16.
  const grid::UniformGrid box(Eigen::Vector3d(-1, 0, 2), 0.1, Eigen::Vector3i(10, 20, 5));
  const AnalyticVelocity f = field({{"type", "deformation"}, {"period", 3.0}}, box);
  const double h = 1e-5;
  for (int n = 0; n < 50; ++n) {
    const Eigen::Vector3d x = box.origin() + Eigen::Vector3d(0.13 + 0.017 * n, 0.41 + 0.029 * n,
                                                             0.07 + 0.0083 * n);
    double divergence = 0.0;
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(a);
      divergence += (f.velocity(x + e, 0.4)[a] - f.velocity(x - e, 0.4)[a]) / (2.0 * h);
    }
    EXPECT_NEAR(divergence, 0.0, 1e-6) << "at " << x.transpose();
  }
  EXPECT_LT(std::abs(f.velocity(Eigen::Vector3d(-1.0, 0.7, 2.2), 0.0).x()), 1e-15);
  EXPECT_LT(std::abs(f.velocity(Eigen::Vector3d(0.3, 2.0, 2.2), 0.0).y()), 1e-15);
  EXPECT_LT(std::abs(f.velocity(Eigen::Vector3d(0.3, 0.7, 2.5), 0.0).z()), 1e-15);
  EXPECT_GT(f.velocity(Eigen::Vector3d(-0.7, 0.5, 2.1), 0.0).norm(), 0.1);  // not vacuous
}

TEST(AnalyticVelocity, DeformationBringsEveryPointBackAtItsPeriod) {
  // u = f(x) cos(πt/T): the flow map is f's at time ∫cos = T/π sin(πt/T), zero at t = T, so
  // every point is back; at T/2 it is as far as it goes. RK4 with 3000 steps: error ~1e-12.
  const AnalyticVelocity f = field({{"type", "deformation"}, {"period", 3.0}});
  const Eigen::Vector3d x0(0.35 + 0.15, 0.35, 0.35);  // on LeVeque's sphere, +x side
  EXPECT_LT((trace(f, x0, 0.0, 3.0, 3000) - x0).norm(), 1e-9);
  EXPECT_GT((trace(f, x0, 0.0, 1.5, 1500) - x0).norm(), 0.1);  // it was carried away
  // Another period: not back at its old T (half-way through the new one's swing).
  const AnalyticVelocity g = field({{"type", "deformation"}, {"period", 2.0}});
  EXPECT_GT((trace(g, x0, 0.0, 3.0, 3000) - x0).norm(), 0.1);
}

TEST(AnalyticVelocity, RigidRotationTurnsOncePerPeriodAboutItsAxis) {
  // About a tilted axis (normalised from its given length): the distance to the axis and
  // the position along it stay, and after one period the point is back (RK4, 4000 steps:
  // error ~1e-12 of the radius); after half a period it is across the axis.
  const Eigen::Vector3d c(0.5, 0.4, 0.3), axis = Eigen::Vector3d(1, 2, 2) / 3.0;
  const AnalyticVelocity f = field(
      {{"type", "rigid_rotation"}, {"center", {0.5, 0.4, 0.3}}, {"axis", {3, 6, 6}},
       {"period", 7.0}});
  const Eigen::Vector3d x0(0.9, 0.1, 0.6);
  const Eigen::Vector3d r0 = (x0 - c) - (x0 - c).dot(axis) * axis;
  EXPECT_LT((trace(f, x0, 0.0, 7.0, 4000) - x0).norm(), 1e-9);
  const Eigen::Vector3d half = trace(f, x0, 0.0, 3.5, 2000);
  EXPECT_LT((half - (x0 - 2.0 * r0)).norm(), 1e-9);
  EXPECT_NEAR((half - c).dot(axis), (x0 - c).dot(axis), 1e-12);
}

TEST(AnalyticVelocity, RigidRotationNeedsAnAxis) {
  nlohmann::json p = test::validated({{"prescribed_velocity",
                                       {{"type", "rigid_rotation"},
                                        {"center", {0, 0, 0}},
                                        {"axis", {0, 0, 0}},
                                        {"period", 1.0}}},
                                      {"water", nlohmann::json::object()}})["prescribed_velocity"];
  try {
    (void)AnalyticVelocity(p, kUnitBox, "/prescribed_velocity");
    FAIL() << "a zero axis was taken";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.json_path(), "/prescribed_velocity/axis");
  }
}

nlohmann::json zalesak_water(int cells, int per_cell) {
  return {{"domain", {{"min", {0, 0, 0}}, {"max", {100, 100, 100}}}},
          {"resolution", cells},
          {"water",
           {{"initial",
             {{{"type", "sphere"}, {"center", {50, 75, 50}}, {"radius", 15}},
              {{"type", "box"},
               {"min", {47.5, 0, -1}},
               {"max", {52.5, 72.5, 101}},
               {"subtract", true}}}},
            {"particles", {{"per_cell", per_cell}}}}},
          {"prescribed_velocity",
           {{"type", "rigid_rotation"}, {"center", {50, 50, 50}}, {"period", 628.0}}}};
}

TEST(PrescribedVelocity, SubtractedBoxCutsZalesaksSlot) {
  // The scene's sphere minus its box against the slotted sphere's exact signed distance:
  // every sample of φ farther than Δx/2 from the surface has the exact sign (the reinitialised φ
  // moves the surface by a fraction of a cell at the slot's corners, not by Δx/2).
  const auto fluid = test::make_fluid(zalesak_water(40, 0), Eigen::Vector3d::Zero());
  const auto& phi = fluid->liquid()->level_set().phi();
  const grid::UniformGrid& lattice = fluid->liquid()->level_set().grid();
  const auto exact = [](const Eigen::Vector3d& p) {
    const double sphere = (p - Eigen::Vector3d(50, 75, 50)).norm() - 15.0;
    const Eigen::Vector3d q = (p - Eigen::Vector3d(50, 36.25, 50)).cwiseAbs() -
                              Eigen::Vector3d(2.5, 36.25, 51);
    const double slot = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    return std::max(sphere, -slot);
  };
  int wrong = 0, slot_air = 0;
  const double dx = fluid->grid().dx();
  for (std::int64_t i = 0; i < static_cast<std::int64_t>(phi.size()); ++i) {
    const Eigen::Vector3d p = lattice.position(Location::Node, i);
    const double e = exact(p);
    if (std::abs(e) > 0.5 * dx && (e < 0.0) != (phi[i] < 0.0)) ++wrong;
    // Samples in the slot inside the sphere's ball: air only because of the subtraction.
    if ((p - Eigen::Vector3d(50, 75, 50)).norm() < 14.0 &&
        std::abs(p.x() - 50.0) < 2.5 - 0.25 * dx && p.y() < 72.0)
      slot_air += phi[i] > 0.0 ? 1 : 0;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(slot_air, 0);
}

/// Runs `fluid` as the runtime would (CFL 0.5, no shells) to `end`; the steps taken.
int run_to(GridFluid& fluid, double end) {
  double t = 0.0;
  int steps = 0;
  while (t < end - 1e-12) {
    const double dt = std::min(fluid.stable_dt(0.5), end - t);
    fluid.advect(t, dt, {}, {});
    fluid.project(dt, {}, {});
    t += dt;
    ++steps;
  }
  return steps;
}

TEST(PrescribedVelocity, TheFieldIsImposedAndNothingIsSolved) {
  // After a step the faces and nodes hold the field at the step's end exactly, no
  // pressure iteration ran, the shape error starts at 0 and grows as the sphere turns.
  auto fluid = test::make_fluid(zalesak_water(16, 0), Eigen::Vector3d::Zero());
  EXPECT_EQ(test::reported(*fluid, "water_symmetric_difference"), 0.0);
  const double dt = fluid->stable_dt(0.5);
  EXPECT_GT(dt, 0.0);
  fluid->advect(0.0, dt, {}, {});
  fluid->project(dt, {}, {});
  const AnalyticVelocity f = field(zalesak_water(16, 0)["prescribed_velocity"], fluid->grid());
  double worst = 0.0;
  for (int a = 0; a < 3; ++a) {
    const auto& u = fluid->mac().face_velocity(a);
    for (std::int64_t i = 0; i < static_cast<std::int64_t>(u.size()); ++i)
      worst = std::max(worst, std::abs(u[i] - f.velocity(fluid->grid().position(face_location(a), i), dt)[a]));
  }
  EXPECT_EQ(worst, 0.0);
  EXPECT_EQ(test::reported(*fluid, "pcg_iterations"), 0.0);
  run_to(*fluid, 60.0);  // a tenth of a turn: the slot has moved by several cells
  EXPECT_GT(test::reported(*fluid, "water_symmetric_difference"),
            0.05 * fluid->liquid()->initial_volume());
}

struct Deformation {
  double loss_half = 0.0, loss_end = 0.0, shape_end = 0.0;
};

/// LeVeque's deformation at `cells`^3 with `per_cell` particles: the volume loss at T/2
/// and T, and the shape error at T, over the starting volume.
Deformation deform(int cells, int per_cell) {
  sdk::Context context;
  context.instance_name = "water";
  context.gravity = Eigen::Vector3d::Zero();
  context.fps = 10.0;  // 30 frames in T: reseeded every 10 (the paper's scenes)
  GridFluid fluid(test::validated(
                      {{"resolution", cells},
                       {"water",
                        {{"initial",
                          {{{"type", "sphere"}, {"center", {0.35, 0.35, 0.35}}, {"radius", 0.15}}}},
                         {"particles", {{"per_cell", per_cell}}}}},
                       {"prescribed_velocity", {{"type", "deformation"}, {"period", 3.0}}}}),
                  context);
  const double v0 = fluid.liquid()->initial_volume();
  Deformation out;
  run_to(fluid, 1.5);
  out.loss_half = 1.0 - fluid.liquid()->level_set().volume() / v0;
  double t = 1.5;
  while (t < 3.0 - 1e-12) {
    const double dt = std::min(fluid.stable_dt(0.5), 3.0 - t);
    fluid.advect(t, dt, {}, {});
    fluid.project(dt, {}, {});
    t += dt;
  }
  out.loss_end = 1.0 - fluid.liquid()->level_set().volume() / v0;
  out.shape_end = test::reported(fluid, "water_symmetric_difference") / v0;
  return out;
}

TEST(PrescribedVelocitySlow, LeVequeDeformationKeepsMoreWaterWithParticles) {
  const Deformation alone = deform(32, 0);
  const Deformation particles = deform(32, 16);
  std::printf(
      "[  figure  ] LeVeque deformation 32^3: volume loss at T/2 %.2f%% alone, %.2f%% with 16 "
      "particles per cell; at T %.2f%% and %.2f%%; shape error at T %.2f and %.2f of V0\n",
      100.0 * alone.loss_half, 100.0 * particles.loss_half, 100.0 * alone.loss_end,
      100.0 * particles.loss_end, alone.shape_end, particles.shape_end);
  EXPECT_LT(std::abs(particles.loss_end), 0.25 * std::abs(alone.loss_end));
}

}  // namespace
}  // namespace shellflow::grid_fluid
