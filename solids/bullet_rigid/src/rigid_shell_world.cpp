#include "shellflow/bullet_rigid/rigid_shell_world.hpp"

// Bullet, double precision (BT_USE_DOUBLE_PRECISION comes with the shellflow::bullet target).
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "shell_plane_collision.hpp"
#include "shellflow/sdk/error.hpp"

// Contact geometry: GImpact (btGImpactMeshShape), not a convex decomposition.
//  - The shells are open, zero-thickness surfaces (cups, boats, plates). A convex
//    decomposition (V-HACD) fills each piece's convex hull, so a cup would collide as a
//    solid block and nothing could rest inside it; GImpact collides the triangles
//    themselves, the same triangles the fluid sees (§3), thickened by a small margin.
//  - It needs no offline decomposition step and no parameters besides the margin.
//  - Costs: triangle–triangle tests between overlapping bodies (bounded by GImpact's
//    box trees), contacts found only within the margin (a thin shell moving more than
//    its margin plus its size in one substep can tunnel: keep the substep small), and
//    vertex-only contacts against the ground plane (ShellPlaneCollision), which is exact
//    for flat faces resting on it.

namespace shellflow::bullet_rigid {

namespace {

constexpr std::uint32_t kStateTag = 0x42524731;  // "BRG1": bullet_rigid state, version 1

btVector3 to_bt(const Eigen::Vector3d& v) {
  return btVector3(v.x(), v.y(), v.z());
}
Eigen::Vector3d to_eigen(const btVector3& v) {
  return Eigen::Vector3d(v.x(), v.y(), v.z());
}
btMatrix3x3 to_bt_basis(const Eigen::Matrix3d& m) {
  return btMatrix3x3(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1),
                     m(2, 2));
}
Eigen::Matrix3d to_eigen(const btMatrix3x3& m) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = m[r][c];
  return out;
}

void write_vector(sdk::StateWriter& out, const btVector3& v) {
  out.write(v.x());
  out.write(v.y());
  out.write(v.z());
}
btVector3 read_vector(sdk::StateReader& in) {
  const double x = in.read<double>();
  const double y = in.read<double>();
  const double z = in.read<double>();
  return btVector3(x, y, z);
}
void write_transform(sdk::StateWriter& out, const btTransform& t) {
  for (int r = 0; r < 3; ++r) write_vector(out, t.getBasis()[r]);
  write_vector(out, t.getOrigin());
}
btTransform read_transform(sdk::StateReader& in) {
  btMatrix3x3 basis;
  for (int r = 0; r < 3; ++r) basis[r] = read_vector(in);
  const btVector3 origin = read_vector(in);
  return btTransform(basis, origin);
}

bool finite(const btVector3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

/// One shell: its spec, mass properties, the mesh in its principal frame, and Bullet's
/// objects (which keep pointers into `indices` and `vertices`: a Body never moves).
struct Body {
  RigidShellSpec spec;
  ShellMassProperties mass;
  sdk::Positions local;            ///< node coordinates in the principal frame
  std::vector<int> indices;        ///< triangles, for Bullet's mesh interface
  std::vector<btScalar> vertices;  ///< `local`, for Bullet's mesh interface
  std::unique_ptr<btTriangleIndexVertexArray> mesh;
  std::unique_ptr<btGImpactMeshShape> shape;
  std::unique_ptr<btRigidBody> rigid;
  Eigen::Vector3d start_centre = Eigen::Vector3d::Zero();  ///< kinematic pose at t = 0
  Eigen::Matrix3d start_rotation = Eigen::Matrix3d::Identity();

  bool dynamic() const { return spec.motion == Motion::Dynamic; }

  /// Kinematic pose at time t: constant velocity of the centre of mass, constant
  /// angular velocity about it (evaluated from t, so no drift accumulates).
  btTransform kinematic_pose(double t) const {
    Eigen::Matrix3d rotation = start_rotation;
    const double rate = spec.angular_velocity.norm();
    if (rate > 0.0)
      rotation = Eigen::AngleAxisd(rate * t, spec.angular_velocity / rate).toRotationMatrix() *
                 start_rotation;
    return btTransform(to_bt_basis(rotation),
                       to_bt(Eigen::Vector3d(start_centre + spec.velocity * t)));
  }
};

/// Another solid's surface as a kinematic mesh in world coordinates (identity pose).
/// Bullet keeps pointers into `indices` and `vertices`: a Collider never moves.
struct Collider {
  const void* triangles_id = nullptr;  ///< the surface's triangle array (identity of the mesh)
  sdk::Positions start;                ///< node positions at the start of advance()
  sdk::Positions velocities;           ///< node velocities [m/s]
  std::vector<int> indices;
  std::vector<btScalar> vertices;
  std::unique_ptr<btTriangleIndexVertexArray> mesh;
  std::unique_ptr<btGImpactMeshShape> shape;
  std::unique_ptr<btRigidBody> rigid;

  /// Nodes at `elapsed` seconds after the start, then the box tree refit.
  void move_to(double elapsed) {
    for (Eigen::Index k = 0; k < start.rows(); ++k)
      for (int c = 0; c < 3; ++c)
        vertices[static_cast<size_t>(3 * k + c)] =
            start(k, c) + (velocities.rows() == start.rows() ? elapsed * velocities(k, c) : 0.0);
    shape->postUpdate();
    shape->updateBound();
    rigid->setWorldTransform(btTransform::getIdentity());
  }
};

}  // namespace

struct RigidShellWorld::Impl {
  RigidWorldSettings settings;
  std::vector<std::unique_ptr<Body>> bodies;
  std::vector<std::unique_ptr<Collider>> colliders;
  std::unique_ptr<btDefaultCollisionConfiguration> configuration;
  std::unique_ptr<btStaticPlaneShape> ground_shape;
  std::unique_ptr<btRigidBody> ground;
  ShellPlaneCollision::CreateFunc shell_plane;  // outlives every dispatcher below
  // Rebuilt by every advance() (see the header): declared last, destroyed first.
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver;
  std::unique_ptr<btDiscreteDynamicsWorld> world;
  int last_substeps = 0;
  int contacts = 0;

  ~Impl() { release_world(); }

  void release_world() {
    // The world's destructor removes the bodies' broadphase proxies, so it goes first.
    world.reset();
    solver.reset();
    dispatcher.reset();
    broadphase.reset();
  }

  /// A fresh broadphase, dispatcher and solver holding the bodies in a fixed order: no
  /// contact manifold, pair cache or tree layout survives from an earlier advance().
  void rebuild_world() {
    release_world();
    broadphase = std::make_unique<btDbvtBroadphase>();
    dispatcher = std::make_unique<btCollisionDispatcher>(configuration.get());
    btGImpactCollisionAlgorithm::registerAlgorithm(dispatcher.get());
    dispatcher->registerCollisionCreateFunc(GIMPACT_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE,
                                            &shell_plane);
    dispatcher->registerCollisionCreateFunc(STATIC_PLANE_PROXYTYPE, GIMPACT_SHAPE_PROXYTYPE,
                                            &shell_plane);
    solver = std::make_unique<btSequentialImpulseConstraintSolver>();
    world = std::make_unique<btDiscreteDynamicsWorld>(dispatcher.get(), broadphase.get(),
                                                      solver.get(), configuration.get());
    world->setGravity(to_bt(settings.gravity));
    world->getSolverInfo().m_numIterations = settings.solver_iterations;
    if (ground) world->addRigidBody(ground.get());
    for (auto& b : bodies) world->addRigidBody(b->rigid.get());
    for (auto& c : colliders) world->addRigidBody(c->rigid.get());
  }

  int count_contacts() const {
    if (!dispatcher) return 0;
    int n = 0;
    for (int i = 0; i < dispatcher->getNumManifolds(); ++i)
      n += dispatcher->getManifoldByIndexInternal(i)->getNumContacts();
    return n;
  }

  const Body& body(int i) const {
    if (i < 0 || i >= static_cast<int>(bodies.size()))
      throw Error("RigidShellWorld: body index " + std::to_string(i) + " out of range [0, " +
                  std::to_string(bodies.size()) + ")");
    return *bodies[static_cast<size_t>(i)];
  }
};

RigidShellWorld::RigidShellWorld(const RigidWorldSettings& settings,
                                 std::vector<RigidShellSpec> specs)
    : m_impl(std::make_unique<Impl>()) {
  auto& impl = *m_impl;
  impl.settings = settings;
  if (!(settings.max_substep > 0.0) || !std::isfinite(settings.max_substep))
    throw Error("RigidShellWorld: max_substep must be a positive number of seconds");
  if (!(settings.margin > 0.0)) throw Error("RigidShellWorld: margin must be positive");
  if (settings.solver_iterations < 1)
    throw Error("RigidShellWorld: solver_iterations must be at least 1");
  impl.configuration = std::make_unique<btDefaultCollisionConfiguration>();

  if (settings.ground) {
    const GroundPlane& g = *settings.ground;
    const double length = g.normal.norm();
    if (!(length > 0.0)) throw Error("RigidShellWorld: the ground normal is the zero vector");
    impl.ground_shape =
        std::make_unique<btStaticPlaneShape>(to_bt(Eigen::Vector3d(g.normal / length)), g.height);
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, impl.ground_shape.get());
    info.m_friction = g.friction;
    info.m_restitution = g.restitution;
    impl.ground = std::make_unique<btRigidBody>(info);
  }

  for (auto& spec : specs) {
    auto b = std::make_unique<Body>();
    b->mass = shell_mass_properties(spec.mesh.positions, spec.mesh.triangles, spec.surface_density);
    const Eigen::Matrix3d& axes = b->mass.principal_axes;
    const Eigen::Vector3d& centre = b->mass.centre_of_mass;
    // Principal-frame coordinates p = Rᵀ (x − c).
    b->local = (spec.mesh.positions.rowwise() - centre.transpose()) * axes;
    b->start_centre = centre;
    b->start_rotation = axes;

    const auto& tris = spec.mesh.triangles;
    b->indices.assign(tris.data(), tris.data() + tris.size());
    b->vertices.assign(b->local.data(), b->local.data() + b->local.size());
    b->mesh = std::make_unique<btTriangleIndexVertexArray>(
        static_cast<int>(tris.rows()), b->indices.data(), static_cast<int>(3 * sizeof(int)),
        static_cast<int>(b->local.rows()), b->vertices.data(),
        static_cast<int>(3 * sizeof(btScalar)));
    b->shape = std::make_unique<btGImpactMeshShape>(b->mesh.get());
    b->shape->setMargin(settings.margin);
    b->shape->updateBound();

    const bool dynamic = spec.motion == Motion::Dynamic;
    const double mass = dynamic ? b->mass.mass : 0.0;  // Bullet: kinematic bodies are massless
    const btVector3 inertia = dynamic ? to_bt(b->mass.principal_moments) : btVector3(0, 0, 0);
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, b->shape.get(), inertia);
    info.m_startWorldTransform = btTransform(to_bt_basis(axes), to_bt(centre));
    info.m_friction = spec.friction;
    info.m_restitution = spec.restitution;
    b->rigid = std::make_unique<btRigidBody>(info);
    if (!dynamic)
      b->rigid->setCollisionFlags(b->rigid->getCollisionFlags() |
                                  btCollisionObject::CF_KINEMATIC_OBJECT);
    // Never sleep: a sleeping body would ignore fluid forces, and the activation state
    // would be one more thing for save() to carry.
    b->rigid->setActivationState(DISABLE_DEACTIVATION);
    b->rigid->setLinearVelocity(to_bt(spec.velocity));
    b->rigid->setAngularVelocity(to_bt(spec.angular_velocity));
    b->rigid->setInterpolationLinearVelocity(to_bt(spec.velocity));
    b->rigid->setInterpolationAngularVelocity(to_bt(spec.angular_velocity));
    b->spec = std::move(spec);
    impl.bodies.push_back(std::move(b));
  }
  impl.rebuild_world();
}

RigidShellWorld::~RigidShellWorld() = default;

void RigidShellWorld::set_colliders(sdk::ShellSet surfaces) {
  auto& impl = *m_impl;
  std::vector<const sdk::ShellSurface*> meshes;
  for (const auto& surface : surfaces)
    if (surface.triangle_count() > 0) meshes.push_back(&surface);
  bool same = meshes.size() == impl.colliders.size();
  for (size_t i = 0; same && i < meshes.size(); ++i)
    same = meshes[i]->triangles.get() == impl.colliders[i]->triangles_id &&
           meshes[i]->node_count() == impl.colliders[i]->start.rows();
  if (!same) {
    impl.release_world();  // the world holds the old colliders' bodies
    impl.colliders.clear();
    for (const auto* surface : meshes) {
      auto c = std::make_unique<Collider>();
      c->triangles_id = surface->triangles.get();
      const auto& tris = *surface->triangles;
      c->indices.resize(static_cast<size_t>(tris.size()));
      for (Eigen::Index t = 0; t < tris.rows(); ++t)
        for (int k = 0; k < 3; ++k) c->indices[static_cast<size_t>(3 * t + k)] = tris(t, k);
      c->vertices.assign(static_cast<size_t>(3 * surface->node_count()), 0.0);
      c->start = surface->positions;
      c->mesh = std::make_unique<btTriangleIndexVertexArray>(
          static_cast<int>(tris.rows()), c->indices.data(), static_cast<int>(3 * sizeof(int)),
          surface->node_count(), c->vertices.data(), static_cast<int>(3 * sizeof(btScalar)));
      c->shape = std::make_unique<btGImpactMeshShape>(c->mesh.get());
      c->shape->setMargin(impl.settings.margin);
      btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, c->shape.get());
      info.m_friction = 1.0;     // the product rule leaves each body's own coefficient
      info.m_restitution = 1.0;  // (as for the ground plane)
      c->rigid = std::make_unique<btRigidBody>(info);
      c->rigid->setCollisionFlags(c->rigid->getCollisionFlags() |
                                  btCollisionObject::CF_KINEMATIC_OBJECT);
      c->rigid->setActivationState(DISABLE_DEACTIVATION);
      impl.colliders.push_back(std::move(c));
    }
  }
  for (size_t i = 0; i < meshes.size(); ++i) {
    Collider& c = *impl.colliders[i];
    c.start = meshes[i]->positions;
    c.velocities = meshes[i]->velocities;
    c.move_to(0.0);
  }
  if (!same) impl.rebuild_world();
}

int RigidShellWorld::collider_count() const {
  return static_cast<int>(m_impl->colliders.size());
}

int RigidShellWorld::body_count() const {
  return static_cast<int>(m_impl->bodies.size());
}

const RigidShellSpec& RigidShellWorld::spec(int body) const {
  return m_impl->body(body).spec;
}

const ShellMassProperties& RigidShellWorld::mass_properties(int body) const {
  return m_impl->body(body).mass;
}

RigidBodyState RigidShellWorld::state(int body) const {
  const Body& b = m_impl->body(body);
  const btTransform& t = b.rigid->getCenterOfMassTransform();
  RigidBodyState s;
  s.centre_of_mass = to_eigen(t.getOrigin());
  s.rotation = to_eigen(t.getBasis());
  if (b.dynamic()) {
    s.velocity = to_eigen(b.rigid->getLinearVelocity());
    s.angular_velocity = to_eigen(b.rigid->getAngularVelocity());
  } else {
    s.velocity = b.spec.velocity;
    s.angular_velocity = b.spec.angular_velocity;
  }
  return s;
}

Eigen::Matrix3d RigidShellWorld::world_inertia(int body) const {
  const Body& b = m_impl->body(body);
  const Eigen::Matrix3d r = to_eigen(b.rigid->getCenterOfMassTransform().getBasis());
  return r * b.mass.principal_moments.asDiagonal() * r.transpose();
}

Eigen::Matrix3d RigidShellWorld::world_inverse_inertia(int body) const {
  const Body& b = m_impl->body(body);
  const Eigen::Matrix3d r = to_eigen(b.rigid->getCenterOfMassTransform().getBasis());
  const Eigen::Vector3d inverse =
      b.mass.principal_moments.unaryExpr([](double m) { return m > 0.0 ? 1.0 / m : 0.0; });
  return r * inverse.asDiagonal() * r.transpose();
}

const Eigen::Vector3d& RigidShellWorld::gravity() const { return m_impl->settings.gravity; }

void RigidShellWorld::node_positions(int body, sdk::Positions& out) const {
  const Body& b = m_impl->body(body);
  const RigidBodyState s = state(body);
  out = (b.local * s.rotation.transpose()).rowwise() + s.centre_of_mass.transpose();
}

void RigidShellWorld::node_velocities(int body, sdk::Positions& out) const {
  const Body& b = m_impl->body(body);
  const RigidBodyState s = state(body);
  out.resize(b.local.rows(), 3);
  for (Eigen::Index i = 0; i < b.local.rows(); ++i) {
    const Eigen::Vector3d r = s.rotation * b.local.row(i).transpose();  // x − c
    out.row(i) = (s.velocity + s.angular_velocity.cross(r)).transpose();
  }
}

void RigidShellWorld::advance(double t, double dt, std::span<const Wrench> wrenches) {
  auto& impl = *m_impl;
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw Error("RigidShellWorld::advance: dt = " + std::to_string(dt) + " s; it must be positive");
  if (!wrenches.empty() && wrenches.size() != impl.bodies.size())
    throw Error("RigidShellWorld::advance: " + std::to_string(wrenches.size()) + " wrenches for " +
                std::to_string(impl.bodies.size()) + " bodies");
  // Equal substeps no longer than max_substep (the relative 1e-12 keeps dt = k·max_substep
  // from rounding up to k + 1 steps).
  const int n =
      std::max(1, static_cast<int>(std::ceil(dt / impl.settings.max_substep * (1.0 - 1e-12))));
  const double h = dt / n;

  impl.rebuild_world();
  for (int k = 0; k < n; ++k) {
    const double t_next = (k + 1 == n) ? t + dt : t + (k + 1) * h;
    // Colliders where their nodes are at the start of this substep.
    for (auto& c : impl.colliders) c->move_to(k * h);
    for (size_t i = 0; i < impl.bodies.size(); ++i) {
      Body& b = *impl.bodies[i];
      if (!b.dynamic()) {
        // Bullet derives a kinematic body's velocity from its last and new transforms
        // (btRigidBody::saveKinematicState) and resolves contacts against it.
        b.rigid->setWorldTransform(b.kinematic_pose(t_next));
      } else if (!wrenches.empty()) {
        // Bullet clears applied forces after every stepSimulation(): apply each substep.
        b.rigid->applyCentralForce(to_bt(wrenches[i].force));
        b.rigid->applyTorque(to_bt(wrenches[i].torque));
      }
    }
    // maxSubSteps = 0: exactly one internal step of length h, no interpolation.
    impl.world->stepSimulation(h, 0, h);
  }
  impl.last_substeps = n;
  impl.contacts = impl.count_contacts();

  for (const auto& b : impl.bodies) {
    const btTransform& x = b->rigid->getCenterOfMassTransform();
    if (!finite(x.getOrigin()) || !finite(b->rigid->getLinearVelocity()) ||
        !finite(b->rigid->getAngularVelocity()))
      throw NumericalError("bullet_rigid: body '" + b->spec.name +
                           "' has a non-finite position or velocity after the step from t = " +
                           std::to_string(t) + " s; reduce 'substep' or the fluid forces");
  }
}

int RigidShellWorld::last_substeps() const {
  return m_impl->last_substeps;
}

int RigidShellWorld::contact_count() const {
  return m_impl->contacts;
}

double RigidShellWorld::kinetic_energy() const {
  double e = 0.0;
  for (int i = 0; i < body_count(); ++i) {
    const Body& b = m_impl->body(i);
    if (!b.dynamic()) continue;
    const RigidBodyState s = state(i);
    e += 0.5 * b.mass.mass * s.velocity.squaredNorm() +
         0.5 * s.angular_velocity.dot(world_inertia(i) * s.angular_velocity);
  }
  return e;
}

double RigidShellWorld::potential_energy() const {
  double e = 0.0;
  for (int i = 0; i < body_count(); ++i) {
    const Body& b = m_impl->body(i);
    if (b.dynamic()) e -= b.mass.mass * m_impl->settings.gravity.dot(state(i).centre_of_mass);
  }
  return e;
}

// The state is everything of a btRigidBody that a step reads and a step writes:
// transform, velocities, and the "interpolation" transform and velocities (Bullet's
// predicted pose, which widens the broadphase boxes of moving bodies). The inverse world
// inertia is a function of the transform (btRigidBody::updateInertiaTensor), applied
// forces are cleared after every step, and the contact caches are rebuilt by advance().
void RigidShellWorld::save(sdk::StateWriter& out) const {
  const auto& impl = *m_impl;
  out.write(kStateTag);
  out.write<std::int64_t>(static_cast<std::int64_t>(impl.bodies.size()));
  for (const auto& b : impl.bodies) {
    const btRigidBody& r = *b->rigid;
    write_transform(out, r.getCenterOfMassTransform());
    write_transform(out, r.getInterpolationWorldTransform());
    write_vector(out, r.getLinearVelocity());
    write_vector(out, r.getAngularVelocity());
    write_vector(out, r.getInterpolationLinearVelocity());
    write_vector(out, r.getInterpolationAngularVelocity());
    out.write(r.getDeactivationTime());
  }
  out.write<std::int32_t>(impl.last_substeps);
  out.write<std::int32_t>(impl.contacts);
}

void RigidShellWorld::restore(sdk::StateReader& in) {
  auto& impl = *m_impl;
  if (in.read<std::uint32_t>() != kStateTag)
    throw Error("bullet_rigid restore(): the state was not saved by bullet_rigid");
  const auto count = in.read<std::int64_t>();
  if (count != static_cast<std::int64_t>(impl.bodies.size()))
    throw Error("bullet_rigid restore(): the state holds " + std::to_string(count) +
                " bodies, this solver has " + std::to_string(impl.bodies.size()));
  for (auto& b : impl.bodies) {
    btRigidBody& r = *b->rigid;
    const btTransform transform = read_transform(in);
    const btTransform interpolation = read_transform(in);
    const btVector3 v = read_vector(in);
    const btVector3 w = read_vector(in);
    const btVector3 v_interpolation = read_vector(in);
    const btVector3 w_interpolation = read_vector(in);
    const double deactivation = in.read<double>();
    r.setCenterOfMassTransform(transform);  // also refreshes the world inverse inertia
    r.setInterpolationWorldTransform(interpolation);
    r.setLinearVelocity(v);
    r.setAngularVelocity(w);
    r.setInterpolationLinearVelocity(v_interpolation);
    r.setInterpolationAngularVelocity(w_interpolation);
    r.setDeactivationTime(deactivation);
    r.clearForces();
  }
  impl.last_substeps = in.read<std::int32_t>();
  impl.contacts = in.read<std::int32_t>();
  impl.rebuild_world();
}

}  // namespace shellflow::bullet_rigid
