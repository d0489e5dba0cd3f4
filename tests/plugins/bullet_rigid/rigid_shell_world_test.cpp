// Dynamics of rigid thin shells in Bullet: free fall, torque-driven rotation with the shell
// inertia, kinematic motion, settling on the ground, and bit-for-bit save/restore.
#include "shellflow/bullet_rigid/rigid_shell_world.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <numbers>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::bullet_rigid {
namespace {

constexpr double kFrame = 1.0 / 24.0;
constexpr double kSubstep = 1.0 / 240.0;

RigidShellSpec body(const std::string& name, geometry::SurfaceMesh mesh,
                    const Eigen::Affine3d& placement = Eigen::Affine3d::Identity()) {
  RigidShellSpec b;
  b.name = name;
  geometry::apply_transform(placement, mesh);
  b.mesh = std::move(mesh);
  return b;
}

Eigen::Affine3d placed(const Eigen::Vector3d& translate, double angle = 0.0,
                       const Eigen::Vector3d& axis = Eigen::Vector3d::UnitY()) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.translate(translate);
  t.rotate(Eigen::AngleAxisd(angle, axis.normalized()));
  return t;
}

RigidWorldSettings no_gravity() {
  RigidWorldSettings s;
  s.gravity.setZero();
  s.max_substep = kSubstep;
  return s;
}

void run_frames(RigidShellWorld& world, double& t, int frames,
                std::span<const Wrench> wrenches = {}) {
  for (int f = 0; f < frames; ++f) {
    world.advance(t, kFrame, wrenches);
    t += kFrame;
  }
}

TEST(RigidShellWorld, FreeFallFollowsTheAnalyticTrajectory) {
  // x(t) = x0 + v0 t + ½ g t², v(t) = v0 + g t. Bullet integrates with symplectic Euler
  // (v += g h, then x += v h): after n = T/h steps v is exact and x carries the known
  // first-order offset ½ g h T, i.e. x_n = x0 + v0 T + g h² n(n+1)/2.
  RigidWorldSettings s;
  s.gravity = Eigen::Vector3d(0.0, -9.81, 0.0);
  s.max_substep = kSubstep;
  const Eigen::Vector3d x0(0.5, 10.0, -1.0), v0(1.0, 2.0, -0.5), w0(0.0, 0.0, 3.0);
  auto sphere = body("ball", geometry::make_sphere(0.3, 2), placed(x0));
  sphere.velocity = v0;
  sphere.angular_velocity = w0;
  const auto initial = sphere.mesh.positions;
  RigidShellWorld world(s, {sphere});
  const Eigen::Vector3d c0 = world.state(0).centre_of_mass;
  ASSERT_LT((c0 - x0).norm(), 1e-14 * x0.norm());  // the sphere's centre is its mass centre

  double t = 0.0;
  run_frames(world, t, 24);  // T = 1 s in 240 substeps
  ASSERT_EQ(world.last_substeps(), 10);
  const double T = 1.0, h = kSubstep, n = 240.0;
  const auto state = world.state(0);
  // Round-off: 240 updates of O(10) numbers, ε = 1.1e-16 → 1e-12 is generous.
  EXPECT_LT((state.velocity - (v0 + s.gravity * T)).norm(), 1e-12);
  const Eigen::Vector3d discrete = c0 + v0 * T + s.gravity * h * h * n * (n + 1) / 2;
  EXPECT_LT((state.centre_of_mass - discrete).norm(), 1e-11);
  const Eigen::Vector3d analytic = c0 + v0 * T + 0.5 * s.gravity * T * T;
  EXPECT_LE((state.centre_of_mass - analytic).norm(), 0.5 * s.gravity.norm() * h * T + 1e-11);

  // A torque-free sphere spins at constant ω (isotropic inertia: no gyroscopic torque);
  // the exponential-map update makes the rotation exp(ω T) up to round-off, and the
  // nodes follow x = R (x0 − c0) + c, v = v_c + ω × (x − c).
  EXPECT_LT((state.angular_velocity - w0).norm(), 1e-12);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(w0.norm() * T, w0.normalized()).matrix();
  sdk::Positions x, v;
  world.node_positions(0, x);
  world.node_velocities(0, v);
  double position_error = 0.0, velocity_error = 0.0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Eigen::Vector3d r = rotation * (initial.row(i).transpose() - c0);
    position_error = std::max(position_error, (x.row(i).transpose() - (discrete + r)).norm());
    velocity_error =
        std::max(velocity_error, (v.row(i).transpose() - (state.velocity + w0.cross(r))).norm());
  }
  EXPECT_LT(position_error, 1e-10);  // round-off of 240 rotation updates
  EXPECT_LT(velocity_error, 1e-10);

  // Kinetic energy: ½ m |v|² + ½ ωᵀ I ω with the shell inertia.
  const auto& mp = world.mass_properties(0);
  const double ke = 0.5 * mp.mass * state.velocity.squaredNorm() + 0.5 * w0.dot(mp.inertia * w0);
  EXPECT_NEAR(world.kinetic_energy(), ke, 1e-12 * ke);
}

/// The analytic inertia of the open box (a, b, c), σ = 1, about its centre of mass: see
/// shell_mass_properties_test.cpp for the derivation; repeated here in closed form.
Eigen::Matrix3d open_box_inertia(double a, double b, double c) {
  const double mb = a * c, mx = b * c, mz = a * b, m = mb + 2 * mx + 2 * mz;
  const double yc = -mb * b / 2 / m;
  const double sxx = mb * a * a / 12 + 2 * mx * a * a / 4 + 2 * mz * a * a / 12;
  const double syy = mb * b * b / 4 + 2 * mx * b * b / 12 + 2 * mz * b * b / 12 - m * yc * yc;
  const double szz = mb * c * c / 12 + 2 * mx * c * c / 12 + 2 * mz * c * c / 4;
  return Eigen::Vector3d(syy + szz, sxx + szz, sxx + syy).asDiagonal();
}

TEST(RigidShellWorld, TorqueGivesTheAngularAccelerationOfTheShellInertia) {
  // Open box (a cup: anisotropic, centre of mass off its geometric centre), turned so its
  // principal axes are not the world axes. I_world = R I_box Rᵀ with the analytic I_box.
  const double a = 0.6, b = 0.4, c = 0.3;
  const Eigen::Affine3d placement = placed({1.0, 2.0, 3.0}, 0.8, {1.0, 2.0, -1.0});
  const Eigen::Matrix3d r = placement.linear();
  const Eigen::Matrix3d inertia = r * open_box_inertia(a, b, c) * r.transpose();

  {
    // About a principal axis: ω stays along it (no gyroscopic torque), so α = τ / I_k
    // for the whole run; ω(T) = α T exactly and the angle is the symplectic-Euler sum
    // α h² n (n + 1) / 2.
    RigidShellWorld world(no_gravity(),
                          {body("cup", geometry::make_open_box({a, b, c}, 2), placement)});
    const Eigen::Vector3d axis = r.col(2);  // the box's z axis
    const double torque = 0.05;             // [N m]
    const std::vector<Wrench> wrench{{Eigen::Vector3d::Zero(), torque * axis}};
    double t = 0.0;
    run_frames(world, t, 12, wrench);  // T = 0.5 s, 120 substeps
    const double alpha = torque / open_box_inertia(a, b, c)(2, 2);
    const auto state = world.state(0);
    // Round-off (the inverse inertia passes through a quaternion each substep): 1e-11.
    EXPECT_LT((state.angular_velocity - alpha * 0.5 * axis).norm(), 1e-11 * alpha);
    const double n = 120.0, h = kSubstep;
    const Eigen::Matrix3d turned =
        state.rotation * world.mass_properties(0).principal_axes.transpose();
    const Eigen::AngleAxisd angle(turned);
    EXPECT_NEAR(std::abs(angle.angle()), alpha * h * h * n * (n + 1) / 2, 1e-10);
    // The centre of mass does not move under a pure torque.
    EXPECT_LT((state.centre_of_mass - world.mass_properties(0).centre_of_mass).norm(), 1e-13);
  }
  {
    // About a general axis, from rest: the first substep gives Δω = h I⁻¹ τ (before any
    // angular velocity exists there is no gyroscopic term).
    RigidWorldSettings s = no_gravity();
    RigidShellWorld world(s, {body("cup", geometry::make_open_box({a, b, c}, 2), placement)});
    const Eigen::Vector3d torque(0.03, -0.02, 0.05);
    const std::vector<Wrench> wrench{{Eigen::Vector3d::Zero(), torque}};
    world.advance(0.0, kSubstep, wrench);
    ASSERT_EQ(world.last_substeps(), 1);
    const Eigen::Vector3d expected = kSubstep * inertia.inverse() * torque;
    // Mesh inertia equals the analytic one to ~1e-12 relative (shell_mass_properties_test).
    EXPECT_LT((world.state(0).angular_velocity - expected).norm(), 1e-11 * expected.norm());
    // The anisotropy matters: an isotropic guess (mean moment) is far off.
    const Eigen::Vector3d isotropic = kSubstep * torque / (inertia.trace() / 3);
    EXPECT_GT((isotropic - expected).norm(), 0.05 * expected.norm());
  }
}

TEST(RigidShellWorld, ForceThroughTheCentreOfMassOnlyTranslates) {
  RigidShellWorld world(no_gravity(), {body("cup", geometry::make_open_box({0.6, 0.4, 0.3}, 2),
                                            placed({0, 1, 0}, 0.4, {1, 0, 0}))});
  const double m = world.mass_properties(0).mass;
  const Eigen::Vector3d force(0.2, 0.1, -0.3);
  const std::vector<Wrench> wrench{{force, Eigen::Vector3d::Zero()}};
  double t = 0.0;
  run_frames(world, t, 6, wrench);  // 0.25 s
  EXPECT_LT((world.state(0).velocity - force / m * 0.25).norm(), 1e-12);
  EXPECT_LT(world.state(0).angular_velocity.norm(), 1e-14);
}

TEST(RigidShellWorld, KinematicBodyMovesAtItsGivenVelocities) {
  // Kinematic: c(t) = c0 + v t, R(t) = exp(ω t) R0, node velocities v + ω × (x − c);
  // gravity and forces do not act on it.
  RigidWorldSettings s;
  s.max_substep = kSubstep;
  auto cup = body("cup", geometry::make_open_box({0.6, 0.4, 0.3}, 2), placed({0, 1, 0}));
  cup.motion = Motion::Kinematic;
  cup.velocity = Eigen::Vector3d(0.5, 0.0, 0.0);
  cup.angular_velocity = Eigen::Vector3d(0.0, 2.0, 1.0);
  const auto initial = cup.mesh.positions;
  RigidShellWorld world(s, {cup});
  const Eigen::Vector3d c0 = world.state(0).centre_of_mass;
  double t = 0.0;
  const std::vector<Wrench> push{{Eigen::Vector3d(100, 0, 0), Eigen::Vector3d(0, 0, 100)}};
  run_frames(world, t, 18, push);  // 0.75 s
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(cup.angular_velocity.norm() * t, cup.angular_velocity.normalized())
          .matrix();
  const Eigen::Vector3d centre = c0 + cup.velocity * t;
  sdk::Positions x, v;
  world.node_positions(0, x);
  world.node_velocities(0, v);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Eigen::Vector3d r = rotation * (initial.row(i).transpose() - c0);
    // Evaluated from t (no accumulation): round-off of one rotation, 1e-14 at O(1) sizes.
    EXPECT_LT((x.row(i).transpose() - (centre + r)).norm(), 1e-14);
    EXPECT_LT((v.row(i).transpose() - (cup.velocity + cup.angular_velocity.cross(r))).norm(),
              1e-14);
  }
  EXPECT_EQ(world.kinetic_energy(), 0.0);  // only dynamic bodies count
}

TEST(RigidShellWorld, KinematicPlateLiftsABoxResting) {
  // A kinematic floor (a grid) rising at 0.5 m/s carries a box: contact with a moving
  // kinematic body uses its velocity (Bullet's saveKinematicState), so the box ends up
  // moving with the plate and above it.
  RigidWorldSettings s;
  s.max_substep = kSubstep;
  auto plate =
      body("plate", geometry::make_grid(2.0, 2.0, 5, 5, geometry::GridPattern::Alternating),
           placed({0, 0, 0}, -std::numbers::pi / 2, {1, 0, 0}));  // normal +y
  plate.motion = Motion::Kinematic;
  plate.velocity = Eigen::Vector3d(0.0, 0.5, 0.0);
  auto box = body("box", geometry::make_box({0.4, 0.2, 0.3}, 2), placed({0, 0.11, 0}));
  RigidShellWorld world(s, {plate, box});
  double t = 0.0;
  run_frames(world, t, 36);  // 1.5 s
  const auto state = world.state(1);
  // Resting contact leaves a velocity error of order g·h = 0.04 m/s in single substeps;
  // averaged over the last frame the box moves with the plate to within 0.05 m/s.
  EXPECT_NEAR(state.velocity.y(), 0.5, 0.05);
  sdk::Positions x;
  world.node_positions(1, x);
  const double plate_height = 0.5 * t;
  EXPECT_GT(x.col(1).minCoeff(), plate_height);         // not fallen through
  EXPECT_LT(x.col(1).minCoeff(), plate_height + 0.05);  // resting on it
}

/// Another solid's surface as the runtime hands it to set_colliders(): a 2 m square plate
/// (a 5 x 5 grid) at rest in the plane y = 0.
sdk::ShellSurface plate_surface() {
  auto mesh = geometry::make_grid(2.0, 2.0, 5, 5, geometry::GridPattern::Alternating);
  geometry::apply_transform(placed({0, 0, 0}, -std::numbers::pi / 2, {1, 0, 0}), mesh);
  sdk::ShellSurface plate;
  plate.name = "cloth/surface";
  plate.positions = mesh.positions;
  plate.velocities = sdk::Positions::Zero(mesh.positions.rows(), 3);
  plate.triangles = std::make_shared<sdk::Triangles>(mesh.triangles);
  return plate;
}

// Lowest node height of a box shell dropped from 0.3 m, after 2 s, with or without
// another solid's plate at y = 0 given through set_colliders() (no ground plane).
double box_height_after_drop(bool with_plate, double* speed = nullptr) {
  RigidWorldSettings s;
  s.max_substep = kSubstep;
  RigidShellWorld world(s,
                        {body("box", geometry::make_box({0.4, 0.2, 0.3}, 2), placed({0, 0.3, 0}))});
  const std::vector<sdk::ShellSurface> colliders{plate_surface()};
  double t = 0.0;
  for (int f = 0; f < 48; ++f) {
    if (with_plate) world.set_colliders(colliders);
    run_frames(world, t, 1);
  }
  if (speed) *speed = world.state(0).velocity.norm();
  sdk::Positions x;
  world.node_positions(0, x);
  return x.col(1).minCoeff();
}

TEST(RigidShellWorld, BoxShellRestsOnAnotherSolidsSurface) {
  // The plate is a kinematic collider mesh: the box lands on it and stays above it,
  // resting within its contact skin (two margins: the box's and the plate's).
  double speed = 0.0;
  const double lowest = box_height_after_drop(true, &speed);
  EXPECT_GT(lowest, 0.0);
  EXPECT_LT(lowest, 0.05);
  // At rest to the velocity error of resting contact in single substeps, g h = 0.04 m/s.
  EXPECT_LT(speed, 0.05);
}

TEST(RigidShellWorld, BoxShellFallsThroughWithoutColliders) {
  // The control case: no collider, no ground: 2 s of free fall from 0.3 m ends ~19 m lower.
  EXPECT_LT(box_height_after_drop(false), -10.0);
}

TEST(RigidShellWorld, BoxShellSettlesOnTheGroundAtRest) {
  // A closed box shell dropped tumbling onto the ground (friction 0.9, restitution 0.2)
  // comes to rest on a face: over the third second (after N = 48 frames of 1/24 s) every
  // frame-end speed stays below the bound.
  RigidWorldSettings s;
  s.max_substep = kSubstep;
  s.ground = GroundPlane{};
  auto box =
      body("box", geometry::make_box({0.4, 0.2, 0.3}, 2), placed({0, 0.6, 0}, 0.45, {1, 0, 1}));
  box.angular_velocity = Eigen::Vector3d(1.0, 0.5, -2.0);
  RigidShellWorld world(s, {box});
  double t = 0.0;
  run_frames(world, t, 48);  // 2 s: landed, bounced, tipped onto a face
  double max_speed = 0.0, max_spin = 0.0;
  for (int f = 0; f < 24; ++f) {
    run_frames(world, t, 1);
    max_speed = std::max(max_speed, world.state(0).velocity.norm());
    max_spin = std::max(max_spin, world.state(0).angular_velocity.norm());
  }
  // Bound 1e-4 m/s and 1e-4 rad/s: the measured residual of the sequential-impulse solver
  // (10 iterations, contacts rebuilt every frame) is 1.9e-5 m/s and 1.6e-5 rad/s; the box
  // was moving at ~3 m/s on impact. Without speculative ground contacts (Bullet's own
  // GImpact–plane test) it is 4e-2 m/s = g·h and this test fails.
  EXPECT_LT(max_speed, 1e-4);
  EXPECT_LT(max_spin, 1e-4);
  const auto state = world.state(0);
  // On a face: one principal axis is vertical to within 1°.
  const Eigen::Vector3d up(0, 1, 0);
  const double alignment = (state.rotation.transpose() * up).cwiseAbs().maxCoeff();
  EXPECT_GT(alignment, std::cos(std::numbers::pi / 180.0));
  // Resting on the contact skin: the lowest node sits one margin above the plane (to
  // 1e-5 m: Bullet's split-impulse position correction leaves micrometres).
  sdk::Positions x;
  world.node_positions(0, x);
  EXPECT_NEAR(x.col(1).minCoeff(), s.margin, 1e-5);
  EXPECT_GT(world.contact_count(), 0);
}

/// A scene with contacts between bodies and with the ground: an open box, a closed box
/// falling into it, and a sphere landing on the ground beside them.
std::vector<RigidShellSpec> pile() {
  std::vector<RigidShellSpec> bodies;
  bodies.push_back(body("cup", geometry::make_open_box({0.6, 0.3, 0.6}, 3), placed({0, 0.2, 0})));
  bodies.push_back(body("box", geometry::make_box({0.2, 0.2, 0.2}, 2),
                        placed({0.05, 0.6, 0.0}, 0.3, {1, 1, 0})));
  bodies.push_back(body("ball", geometry::make_sphere(0.15, 2), placed({0.7, 0.5, 0.1})));
  bodies.back().velocity = Eigen::Vector3d(-0.5, 0, 0);
  return bodies;
}

RigidWorldSettings with_ground() {
  RigidWorldSettings s;
  s.max_substep = kSubstep;
  s.ground = GroundPlane{};
  return s;
}

sdk::StateBuffer saved(const RigidShellWorld& world) {
  sdk::StateBuffer buffer;
  sdk::StateWriter writer(buffer);
  world.save(writer);
  return buffer;
}

void restore(RigidShellWorld& world, const sdk::StateBuffer& buffer) {
  sdk::StateReader reader(buffer);
  world.restore(reader);
  EXPECT_TRUE(reader.at_end());
}

/// Node positions and velocities of every body, concatenated.
std::vector<double> nodes(const RigidShellWorld& world) {
  std::vector<double> out;
  sdk::Positions x;
  for (int i = 0; i < world.body_count(); ++i) {
    world.node_positions(i, x);
    out.insert(out.end(), x.data(), x.data() + x.size());
    world.node_velocities(i, x);
    out.insert(out.end(), x.data(), x.data() + x.size());
  }
  return out;
}

TEST(RigidShellWorld, SaveRestoreAdvanceIsBitForBit) {
  RigidShellWorld world(with_ground(), pile());
  double t = 0.0;
  run_frames(world, t, 12);  // 0.5 s: bodies in contact with the ground and each other
  ASSERT_GT(world.contact_count(), 0) << "the check needs live contacts (warm-start caches)";
  const sdk::StateBuffer at_n = saved(world);
  const double t_n = t;

  run_frames(world, t, 6);
  const sdk::StateBuffer first = saved(world);
  const auto first_nodes = nodes(world);

  restore(world, at_n);
  EXPECT_EQ(saved(world), at_n);  // restore(save()) is the identity on the state
  t = t_n;
  run_frames(world, t, 6);
  EXPECT_EQ(saved(world), first);  // byte-wise
  const auto second_nodes = nodes(world);
  ASSERT_EQ(first_nodes.size(), second_nodes.size());
  EXPECT_EQ(
      std::memcmp(first_nodes.data(), second_nodes.data(), first_nodes.size() * sizeof(double)), 0);

  // A freshly built world restored from the same bytes takes the same path (a
  // checkpoint restart).
  RigidShellWorld fresh(with_ground(), pile());
  restore(fresh, at_n);
  t = t_n;
  run_frames(fresh, t, 6);
  EXPECT_EQ(saved(fresh), first);

  // The state really moved between n and n + 6 frames (the comparison is not vacuous).
  EXPECT_NE(first, at_n);
}

TEST(RigidShellWorld, RestoreRejectsAForeignState) {
  RigidShellWorld world(with_ground(), pile());
  RigidShellWorld other(with_ground(), {pile().front()});
  EXPECT_THROW(restore(world, saved(other)), Error);
  sdk::StateBuffer junk(16, 0);
  EXPECT_THROW(restore(world, junk), Error);
}

}  // namespace
}  // namespace shellflow::bullet_rigid
