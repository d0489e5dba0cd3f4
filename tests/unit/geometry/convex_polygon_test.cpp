// ConvexPolygon: a triangle clipped into a box, with known answers: the plane x + y + z = 3/2
// cuts the unit cube in a regular hexagon through the midpoints of six edges (side √½, area
// 3√3/4, centroid the cube's centre); a triangle inside the box is kept whole.
#include <gtest/gtest.h>

#include <cmath>

#include "shellflow/geometry/convex_polygon.hpp"

namespace shellflow::geometry {
namespace {

TEST(ConvexPolygon, ALargeTriangleInTheCubesDiagonalPlaneClipsToTheRegularHexagon) {
  // A triangle of the plane x + y + z = 1.5 far larger than the cube.
  const ConvexPolygon triangle = ConvexPolygon::triangle({Eigen::Vector3d(10.0, -4.25, -4.25),
                                                          Eigen::Vector3d(-4.25, 10.0, -4.25),
                                                          Eigen::Vector3d(-4.25, -4.25, 10.0)});
  const ConvexPolygon hexagon =
      clip_to_box(triangle, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  ASSERT_EQ(hexagon.count, 6);
  for (int v = 0; v < hexagon.count; ++v) {
    EXPECT_NEAR(hexagon.corner[v].sum(), 1.5, 1e-12);
    // Each corner is an edge's midpoint: one coordinate ½, the others 0 and 1.
    const Eigen::Vector3d c = hexagon.corner[v];
    EXPECT_NEAR((c.array() - 0.5).abs().sum(), 1.0, 1e-12);
  }
  const PolygonMoments m = moments(hexagon);
  EXPECT_NEAR(m.area, 3.0 * std::sqrt(3.0) / 4.0, 1e-12);
  EXPECT_NEAR((m.centroid - Eigen::Vector3d::Constant(0.5)).norm(), 0.0, 1e-12);
}

TEST(ConvexPolygon, ATriangleInsideTheBoxIsKeptWholeAndOneOutsideVanishes) {
  const TriangleCorners c = {Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.8, 0.2, 0.3),
                             Eigen::Vector3d(0.1, 0.9, 0.3)};
  const ConvexPolygon kept =
      clip_to_box(ConvexPolygon::triangle(c), Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  ASSERT_EQ(kept.count, 3);
  EXPECT_NEAR(moments(kept).area, 0.5 * 0.7 * 0.7, 1e-15);
  EXPECT_NEAR((moments(kept).centroid - (c[0] + c[1] + c[2]) / 3.0).norm(), 0.0, 1e-15);
  const ConvexPolygon gone = clip_to_box(ConvexPolygon::triangle(c), Eigen::Vector3d::Constant(2.0),
                                         Eigen::Vector3d::Constant(3.0));
  EXPECT_LT(gone.count, 3);
  EXPECT_EQ(moments(gone).area, 0.0);
}

}  // namespace
}  // namespace shellflow::geometry
