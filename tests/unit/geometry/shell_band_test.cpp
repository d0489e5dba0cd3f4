// ShellBand and SweptPointInvalidator: the sparse band equals the brute-force set of
// samples inside the enlarged triangle boxes; clear() empties it; grid invalidation
// equals point_invalidated applied to every sample.

#include "shellflow/geometry/shell_band.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "shellflow/geometry/swept_point.hpp"
#include "shellflow/geometry/swept_point_invalidator.hpp"
#include "test_meshes.hpp"

namespace shellflow::geometry {
namespace {

using grid::Location;

const grid::UniformGrid kGrid(Eigen::Vector3d::Constant(-0.6), 0.05, Eigen::Vector3i(24, 22, 20));

test::Mesh wavy_cloth() {
  test::Mesh m = test::make_sheet(0.8, 0.7, 17, 15);
  for (int i = 0; i < m.positions.rows(); ++i) {
    const double x = m.positions(i, 0) - 0.4, y = m.positions(i, 1) - 0.35;
    m.positions.row(i) = Eigen::RowVector3d(x, y, 0.1 * std::sin(7.0 * x) + 0.013);
  }
  return m;
}

TEST(ShellBand, MatchesBruteForceAndClears) {
  const test::Mesh cloth = wavy_cloth();
  const TriangleMesh mesh(cloth.positions, cloth.triangles);
  ShellBand band(kGrid);
  const double margin = 0.06;
  band.add(mesh, margin);
  for (const Location location : grid::kAllLocations) {
    std::vector<std::int64_t> expected;
    for (std::int64_t i = 0; i < kGrid.size(location); ++i) {
      const Eigen::Vector3d x = kGrid.position(location, i);
      for (int t = 0; t < mesh.triangle_count(); ++t) {
        if (mesh.box(t).inflated(margin).contains(x)) {
          expected.push_back(i);
          break;
        }
      }
    }
    std::vector<std::int64_t> found(band.samples(location).begin(), band.samples(location).end());
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected);
    ASSERT_GT(found.size(), 0u);
    for (const std::int64_t i : expected) EXPECT_TRUE(band.contains(location, i));
  }
  band.clear();
  for (const Location location : grid::kAllLocations) {
    EXPECT_TRUE(band.samples(location).empty());
    const auto flags = band.flags(location);
    EXPECT_TRUE(std::all_of(flags.begin(), flags.end(), [](std::uint8_t f) { return f == 0; }));
  }
}

TEST(SweptPointInvalidator, MatchesPerSampleTest) {
  const test::Mesh start = wavy_cloth();
  test::Mesh end = start;
  // Move by 1.5 cells up and a bit sideways so that many samples are swept.
  for (int i = 0; i < end.positions.rows(); ++i) {
    end.positions.row(i) += Eigen::RowVector3d(0.01, -0.02, 0.075 + 0.02 * end.positions(i, 0));
  }
  const TriangleMesh m0(start.positions, start.triangles), m1(end.positions, end.triangles);
  const double epsilon = 1e-3 * kGrid.dx();
  const SweptPointInvalidator invalidator(kGrid, epsilon);
  for (const Location location : {Location::Node, Location::FaceZ}) {
    std::vector<std::uint8_t> invalid(kGrid.size(location), 0);
    std::vector<std::int64_t> list;
    const std::int64_t added = invalidator.invalidate(location, m0, m1, invalid, list);
    EXPECT_EQ(added, static_cast<std::int64_t>(list.size()));
    std::int64_t expected = 0;
    for (std::int64_t i = 0; i < kGrid.size(location); ++i) {
      const Eigen::Vector3d p = kGrid.position(location, i);
      bool hit = false;
      for (int t = 0; t < m0.triangle_count() && !hit; ++t) {
        // Prefilter (exact): p can only be hit inside the swept box grown by ε.
        Aabb swept = m0.box(t);
        swept.extend(m1.box(t));
        if (!swept.inflated(epsilon).contains(p)) continue;
        hit = point_invalidated(p, m0.corners(t), m1.corners(t), epsilon, invalidator.tolerance());
      }
      ASSERT_EQ(hit, invalid[i] != 0) << "sample " << i;
      expected += hit;
    }
    EXPECT_EQ(added, expected);
    // The cloth covers ~0.56 of a 0.8 x 0.7 slab moving 1.5 cells: hundreds of samples.
    EXPECT_GT(added, 200);
    // A second call adds nothing (all already flagged).
    EXPECT_EQ(invalidator.invalidate(location, m0, m1, invalid, list), 0);
  }
}

}  // namespace
}  // namespace shellflow::geometry
