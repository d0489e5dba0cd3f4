#pragma once
// ShellPlaneCollision: contact between a GImpact shell and the static ground plane, with
// speculative contacts. Private to bullet_rigid (includes Bullet).
//
// Bullet's own GImpact-vs-plane test (btGImpactCollisionAlgorithm::
// gimpacttrimeshpart_vs_plane_collision) reports a vertex only while it is *inside* the
// margin. A shell resting on the ground sits exactly at the margin, so the contact is
// found in one substep and lost in the next, and the body falls freely for a substep now
// and then (velocity spikes of g·h). Here every vertex closer than the manifold's
// contact-breaking threshold becomes a contact point with its signed gap; Bullet's
// sequential-impulse solver lets a positive gap close within the step but no further
// (speculative contact, as its convex–convex algorithms do), which keeps resting contact
// steady. The persistent manifold keeps the four points spanning the largest area.

#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionCreateFunc.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>

namespace shellflow::bullet_rigid {

class ShellPlaneCollision final : public btActivatingCollisionAlgorithm {
 public:
  ShellPlaneCollision(const btCollisionAlgorithmConstructionInfo& info,
                      const btCollisionObjectWrapper* body0, const btCollisionObjectWrapper* body1);
  ~ShellPlaneCollision() override;

  void processCollision(const btCollisionObjectWrapper* body0,
                        const btCollisionObjectWrapper* body1, const btDispatcherInfo& info,
                        btManifoldResult* result) override;
  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return btScalar(1);
  }
  void getAllContactManifolds(btManifoldArray& manifolds) override;

  /// Register for (GIMPACT_SHAPE_PROXYTYPE, STATIC_PLANE_PROXYTYPE) and the reverse order;
  /// must outlive the dispatcher.
  struct CreateFunc : public btCollisionAlgorithmCreateFunc {
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                   const btCollisionObjectWrapper* body0,
                                                   const btCollisionObjectWrapper* body1) override;
  };

 private:
  btPersistentManifold* m_manifold = nullptr;
};

}  // namespace shellflow::bullet_rigid
