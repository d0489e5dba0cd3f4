#include "shellflow/geometry/swept_triangle_bvh.hpp"

namespace shellflow::geometry {

SweptTriangleBvh::SweptTriangleBvh(const TriangleMesh& start, const TriangleMesh& end,
                                   double max_degradation)
    : m_start(start), m_end(end), m_max_degradation(max_degradation) {
  if (!start.same_topology(end)) {
    throw Error("SweptTriangleBvh: start and end meshes differ in node or triangle count");
  }
  m_start.swept_boxes(m_end, m_boxes);
  m_bvh.build(m_boxes);
}

bool SweptTriangleBvh::update(const TriangleMesh& start, const TriangleMesh& end) {
  if (!start.same_topology(end) || !start.same_topology(m_start)) {
    throw Error("SweptTriangleBvh::update: the mesh topology changed; construct a new one");
  }
  m_start = start;
  m_end = end;
  m_start.swept_boxes(m_end, m_boxes);
  return m_bvh.refit_or_rebuild(m_boxes, m_max_degradation);
}

}  // namespace shellflow::geometry
