// UniformGrid: the documented flat layout, its inverse, sample positions per location,
// and the box-to-index-range helper against brute force.

#include "shellflow/grid/uniform_grid.hpp"

#include <gtest/gtest.h>

#include <random>

namespace shellflow::grid {
namespace {

const UniformGrid kGrid(Eigen::Vector3d(-1.0, 0.5, 2.0), 0.25, Eigen::Vector3i(5, 3, 4));

TEST(UniformGrid, CountsAndLayout) {
  EXPECT_EQ(kGrid.counts(Location::Node), Eigen::Vector3i(6, 4, 5));
  EXPECT_EQ(kGrid.counts(Location::Cell), Eigen::Vector3i(5, 3, 4));
  EXPECT_EQ(kGrid.counts(Location::FaceX), Eigen::Vector3i(6, 3, 4));
  EXPECT_EQ(kGrid.counts(Location::FaceY), Eigen::Vector3i(5, 4, 4));
  EXPECT_EQ(kGrid.counts(Location::FaceZ), Eigen::Vector3i(5, 3, 5));
  // x fastest: index = i + ni (j + nj k).
  EXPECT_EQ(kGrid.index(Location::Node, 1, 2, 3), 1 + 6 * (2 + 4 * 3));
  for (const Location location : kAllLocations) {
    for (std::int64_t i = 0; i < kGrid.size(location); ++i) {
      const Eigen::Vector3i ijk = kGrid.coordinates(location, i);
      ASSERT_TRUE(kGrid.contains(location, ijk));
      ASSERT_EQ(kGrid.index(location, ijk), i);
    }
  }
}

TEST(UniformGrid, Positions) {
  // Exact in binary: dx = 1/4 and small integers.
  EXPECT_EQ(kGrid.position(Location::Node, Eigen::Vector3i(1, 0, 2)),
            Eigen::Vector3d(-0.75, 0.5, 2.5));
  EXPECT_EQ(kGrid.position(Location::Cell, Eigen::Vector3i(0, 0, 0)),
            Eigen::Vector3d(-0.875, 0.625, 2.125));
  EXPECT_EQ(kGrid.position(Location::FaceX, Eigen::Vector3i(0, 0, 0)),
            Eigen::Vector3d(-1.0, 0.625, 2.125));
  EXPECT_EQ(kGrid.position(Location::FaceY, Eigen::Vector3i(0, 0, 0)),
            Eigen::Vector3d(-0.875, 0.5, 2.125));
  EXPECT_EQ(kGrid.position(Location::FaceZ, Eigen::Vector3i(0, 0, 0)),
            Eigen::Vector3d(-0.875, 0.625, 2.0));
  EXPECT_EQ(kGrid.upper(), Eigen::Vector3d(0.25, 1.25, 3.0));
}

TEST(UniformGrid, SamplesInBoxMatchBruteForce) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.5, 3.5);
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    if (trial % 10 == 0) b = a;  // degenerate box
    const Eigen::Vector3d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    for (const Location location : kAllLocations) {
      const IndexBox box = kGrid.samples_in_box(location, lo, hi);
      for (std::int64_t i = 0; i < kGrid.size(location); ++i) {
        const Eigen::Vector3d x = kGrid.position(location, i);
        const Eigen::Vector3i ijk = kGrid.coordinates(location, i);
        const bool in_box = (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
        const bool in_range = !box.empty() && (ijk.array() >= box.lo.array()).all() &&
                              (ijk.array() <= box.hi.array()).all();
        ASSERT_EQ(in_box, in_range);
      }
    }
  }
  // Far outside: empty, no overflow.
  EXPECT_TRUE(kGrid
                  .samples_in_box(Location::Node, Eigen::Vector3d::Constant(1e30),
                                  Eigen::Vector3d::Constant(2e30))
                  .empty());
}

}  // namespace
}  // namespace shellflow::grid
