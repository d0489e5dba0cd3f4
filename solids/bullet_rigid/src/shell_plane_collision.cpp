#include "shell_plane_collision.hpp"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>

#include <new>

namespace shellflow::bullet_rigid {

ShellPlaneCollision::ShellPlaneCollision(const btCollisionAlgorithmConstructionInfo& info,
                                         const btCollisionObjectWrapper* body0,
                                         const btCollisionObjectWrapper* body1)
    : btActivatingCollisionAlgorithm(info, body0, body1) {
  m_manifold =
      m_dispatcher->getNewManifold(body0->getCollisionObject(), body1->getCollisionObject());
}

ShellPlaneCollision::~ShellPlaneCollision() {
  if (m_manifold) m_dispatcher->releaseManifold(m_manifold);
}

void ShellPlaneCollision::getAllContactManifolds(btManifoldArray& manifolds) {
  if (m_manifold) manifolds.push_back(m_manifold);
}

void ShellPlaneCollision::processCollision(const btCollisionObjectWrapper* body0,
                                           const btCollisionObjectWrapper* body1,
                                           const btDispatcherInfo& /*info*/,
                                           btManifoldResult* result) {
  if (!m_manifold) return;
  const bool plane_first = body0->getCollisionShape()->getShapeType() == STATIC_PLANE_PROXYTYPE;
  const btCollisionObjectWrapper* shell_wrap = plane_first ? body1 : body0;
  const btCollisionObjectWrapper* plane_wrap = plane_first ? body0 : body1;
  const auto* shell = static_cast<const btGImpactMeshShape*>(shell_wrap->getCollisionShape());
  const auto* plane = static_cast<const btStaticPlaneShape*>(plane_wrap->getCollisionShape());
  result->setPersistentManifold(m_manifold);

  // The plane {x : n·x = c} in world coordinates.
  const btTransform& plane_pose = plane_wrap->getWorldTransform();
  const btVector3 n = plane_pose.getBasis() * plane->getPlaneNormal();
  const btScalar c = plane->getPlaneConstant() + n.dot(plane_pose.getOrigin());
  const btScalar margin = shell->getMargin() + plane->getMargin();
  const btScalar threshold = m_manifold->getContactBreakingThreshold();
  const btTransform& pose = shell_wrap->getWorldTransform();

  // Whole shell farther than the threshold: nothing to add (its box's lowest corner).
  btVector3 lo, hi;
  shell->getAabb(pose, lo, hi);
  const btVector3 lowest(n.x() >= 0 ? lo.x() : hi.x(), n.y() >= 0 ? lo.y() : hi.y(),
                         n.z() >= 0 ? lo.z() : hi.z());
  if (n.dot(lowest) - c - margin < threshold) {
    for (int p = 0; p < shell->getMeshPartCount(); ++p) {
      const btGImpactMeshShapePart* part = shell->getMeshPart(p);
      part->lockChildShapes();
      btVector3 vertex;
      for (int v = 0; v < part->getVertexCount(); ++v) {
        part->getVertex(v, vertex);
        const btVector3 x = pose(vertex);
        const btScalar gap = n.dot(x) - c - margin;  // < 0: penetrating the skin
        if (gap >= threshold) continue;
        // addContactPoint(normal on B, point on B, distance); B is body1.
        if (plane_first)
          result->addContactPoint(-n, x - n * margin, gap);
        else
          result->addContactPoint(n, x - n * (gap + margin), gap);
      }
      part->unlockChildShapes();
    }
  }
  result->refreshContactPoints();
}

btCollisionAlgorithm* ShellPlaneCollision::CreateFunc::CreateCollisionAlgorithm(
    btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* body0,
    const btCollisionObjectWrapper* body1) {
  void* memory = info.m_dispatcher1->allocateCollisionAlgorithm(sizeof(ShellPlaneCollision));
  return new (memory) ShellPlaneCollision(info, body0, body1);
}

}  // namespace shellflow::bullet_rigid
