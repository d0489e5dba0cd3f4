// Gauss–Jacobi refill (§3): invalid samples take the average of valid visible one-ring
// neighbours, then object values where no visible neighbour exists. A field constant on
// each side of a sheet must be refilled with that side's value only.

#include "shellflow/geometry/gauss_jacobi_refill.hpp"

#include <gtest/gtest.h>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid/sparse_samples.hpp"
#include "test_meshes.hpp"

namespace shellflow::geometry {
namespace {

using grid::Location;

/// Wedge thickness: 1e-3 dx, the 2011 PhysBAM default (collision_thickness in
/// PhysBAM_Geometry/Grids_Uniform_Collisions/GRID_BASED_COLLISION_GEOMETRY_UNIFORM.cpp).
constexpr double kDx = 1.0 / 16.0;
constexpr double kEpsilon = 1e-3 * kDx;

/// A 16^3 unit grid cut by a tilted sheet that extends past the domain on every side
/// (so there is no way around it).
struct Cut {
  grid::UniformGrid grid{Eigen::Vector3d::Zero(), kDx, Eigen::Vector3i::Constant(16)};
  test::Mesh sheet;
  TriangleMesh view;
  TriangleBvh bvh;
  Cut() {
    sheet = test::make_sheet(3.0, 3.0, 13, 13);
    for (int i = 0; i < sheet.positions.rows(); ++i) {
      const double x = sheet.positions(i, 0) - 1.0, y = sheet.positions(i, 1) - 1.0;
      // Plane z = 0.4513 + 0.1 x + 0.05 y: no sample lies within ε/2 of it (an offset of
      // 0.4500 would put nodes exactly on it; those are "inside" and take object values).
      sheet.positions.row(i) = Eigen::RowVector3d(x, y, 0.4513 + 0.1 * x + 0.05 * y);
    }
    view = TriangleMesh(sheet.positions, sheet.triangles);
    bvh = TriangleBvh(view);
  }
  static double side(const Eigen::Vector3d& x) {
    return x.z() - (0.4513 + 0.1 * x.x() + 0.05 * x.y());
  }
};

template <class T>
void check_two_sided(Location location, const T& above, const T& below) {
  Cut cut;
  const WedgeCaster caster(cut.bvh, kEpsilon);
  const std::int64_t n = cut.grid.size(location);
  std::vector<T> values(n);
  std::vector<std::uint8_t> valid(n, 1);
  for (std::int64_t i = 0; i < n; ++i) {
    values[i] = Cut::side(cut.grid.position(location, i)) > 0 ? above : below;
  }
  // Invalidate a two-cell band on each side of the sheet, writing garbage there.
  ShellBand band(cut.grid);
  band.add(cut.view, 2.0 * kDx);
  const auto invalid = band.samples(location);
  ASSERT_GT(invalid.size(), 100u);
  for (const std::int64_t i : invalid) {
    valid[i] = 0;
    values[i] = 1000.0 * above;
  }
  const GaussJacobiRefill refill(cut.grid, location);
  const RefillStats stats =
      refill.run(values, valid, invalid, refill.wedge_visibility(caster),
                    [&](std::int64_t, std::int64_t) { return T(0.5 * (above + below)); });
  EXPECT_GT(stats.neighbour_iterations, 1);
  EXPECT_EQ(stats.isolated, 0);
  int wrong = 0;
  for (const std::int64_t i : invalid) {
    ASSERT_EQ(valid[i], 1);
    const T expected = Cut::side(cut.grid.position(location, i)) > 0 ? above : below;
    // An average of equal values is exact in floating point only up to the division:
    // (k v) / k differs from v by at most one ulp per add, so 1e-12 relative.
    if ((values[i] - expected).norm() > 1e-12) ++wrong;
  }
  EXPECT_EQ(wrong, 0);
}

TEST(GaussJacobiRefill, ScalarOnNodesKeepsEachSidesValue) {
  check_two_sided<Eigen::Matrix<double, 1, 1>>(Location::Node, Eigen::Matrix<double, 1, 1>(2.0),
                                               Eigen::Matrix<double, 1, 1>(-3.0));
}

TEST(GaussJacobiRefill, VectorOnFacesKeepsEachSidesValue) {
  check_two_sided<Eigen::Vector3d>(Location::FaceZ, Eigen::Vector3d(1, 2, 3),
                                   Eigen::Vector3d(-4, 5, -6));
  check_two_sided<Eigen::Vector3d>(Location::FaceX, Eigen::Vector3d(1, 2, 3),
                                   Eigen::Vector3d(-4, 5, -6));
}

// Plain double works too (the arithmetic branch), on cells.
TEST(GaussJacobiRefill, DoubleOnCellsKeepsEachSidesValue) {
  Cut cut;
  const WedgeCaster caster(cut.bvh, kEpsilon);
  const Location location = Location::Cell;
  const std::int64_t n = cut.grid.size(location);
  std::vector<double> values(n);
  std::vector<std::uint8_t> valid(n, 1);
  for (std::int64_t i = 0; i < n; ++i) {
    values[i] = Cut::side(cut.grid.position(location, i)) > 0 ? 7.0 : -1.0;
  }
  ShellBand band(cut.grid);
  band.add(cut.view, 1.5 * kDx);
  for (const std::int64_t i : band.samples(location)) {
    valid[i] = 0;
    values[i] = 0.0;
  }
  const GaussJacobiRefill refill(cut.grid, location);
  refill.run(values, valid, band.samples(location), refill.wedge_visibility(caster),
                     [](std::int64_t, std::int64_t) { return 0.0; });
  for (const std::int64_t i : band.samples(location)) {
    const double expected = Cut::side(cut.grid.position(location, i)) > 0 ? 7.0 : -1.0;
    EXPECT_NEAR(values[i], expected, 1e-12);  // one-ulp-per-add averaging, as above
  }
}

// Ignoring visibility mixes the sides: the test above could fail.
TEST(GaussJacobiRefill, WithoutVisibilityTheSidesMix) {
  Cut cut;
  const Location location = Location::Node;
  const std::int64_t n = cut.grid.size(location);
  std::vector<double> values(n);
  std::vector<std::uint8_t> valid(n, 1);
  for (std::int64_t i = 0; i < n; ++i) {
    values[i] = Cut::side(cut.grid.position(location, i)) > 0 ? 1.0 : -1.0;
  }
  ShellBand band(cut.grid);
  band.add(cut.view, 2.0 * kDx);
  for (const std::int64_t i : band.samples(location)) valid[i] = 0;
  const GaussJacobiRefill refill(cut.grid, location);
  refill.run(
      values, valid, band.samples(location), [](std::int64_t, std::int64_t) { return true; },
      [](std::int64_t, std::int64_t) { return 0.0; });
  int mixed = 0;
  for (const std::int64_t i : band.samples(location))
    mixed += std::abs(std::abs(values[i]) - 1.0) > 1e-3;
  EXPECT_GT(mixed, 10);
}

// A closed box holds only invalid nodes: none has a valid visible neighbour, so the
// object value fills them (here the object velocity (0, 0, 2)), and outside keeps its value.
TEST(GaussJacobiRefill, EnclosedPocketTakesObjectValues) {
  const grid::UniformGrid grid(Eigen::Vector3d::Constant(-0.5), 1.0 / 16.0,
                               Eigen::Vector3i::Constant(16));
  const test::Mesh box = test::make_closed_box(Eigen::Vector3d::Constant(0.53), 4);
  const TriangleMesh view(box.positions, box.triangles);
  const TriangleBvh bvh(view);
  const WedgeCaster caster(bvh, kEpsilon);
  const Location location = Location::Node;
  const std::int64_t n = grid.size(location);
  std::vector<Eigen::Vector3d> values(n, Eigen::Vector3d(1, 0, 0));
  std::vector<std::uint8_t> valid(n, 1);
  std::vector<std::int64_t> invalid;
  for (std::int64_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = grid.position(location, i);
    if ((x.array().abs() < 0.265 + 1.5 / 16.0).all()) {  // the pocket plus a band outside
      invalid.push_back(i);
      valid[i] = 0;
      values[i] = Eigen::Vector3d(99, 99, 99);
    }
  }
  const GaussJacobiRefill refill(grid, location);
  const RefillStats stats = refill.run(
      values, valid, invalid, refill.wedge_visibility(caster),
      [](std::int64_t, std::int64_t) { return Eigen::Vector3d(0, 0, 2); });
  EXPECT_GT(stats.from_neighbours, 0);
  EXPECT_GT(stats.from_object, 0);
  for (const std::int64_t i : invalid) {
    const Eigen::Vector3d x = grid.position(location, i);
    const bool inside = (x.array().abs() < 0.265).all();
    // Exact-value averages: one ulp per add (1e-12 relative is ample).
    EXPECT_NEAR((values[i] - (inside ? Eigen::Vector3d(0, 0, 2) : Eigen::Vector3d(1, 0, 0))).norm(),
                0.0, 1e-12);
  }
}

// The refill reads only the candidates and their one-ring, so values held in a
// grid::SparseSamples with just those samples give the dense result bit for bit (the
// swept-node refill and the §5.1 jumps keep their scratch that way), and the samples
// outside it are never asked for.
TEST(GaussJacobiRefill, SparseSamplesGiveTheDenseResultBitForBit) {
  Cut cut;
  const WedgeCaster caster(cut.bvh, kEpsilon);
  const Location location = Location::Node;
  const std::int64_t n = cut.grid.size(location);
  std::vector<double> dense(n);
  for (std::int64_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = cut.grid.position(location, i);
    dense[i] = Cut::side(x) > 0 ? 1.0 + x.x() : -2.0 + x.y() * x.z();
  }
  ShellBand band(cut.grid);
  band.add(cut.view, 2.0 * kDx);
  const auto invalid = band.samples(location);
  std::vector<std::uint8_t> valid_dense(n, 1);
  for (const std::int64_t i : invalid) valid_dense[i] = 0;
  std::vector<std::uint8_t> valid_sparse = valid_dense;

  grid::SparseSamples<double> sparse;
  sparse.resize(n);
  const Eigen::Vector3i counts = cut.grid.counts(location);
  for (const std::int64_t i : invalid) {
    const Eigen::Vector3i ijk = cut.grid.coordinates(location, i);
    sparse.insert(i, dense[i]);
    for (int axis = 0; axis < 3; ++axis)
      for (const int side : {-1, 1}) {
        Eigen::Vector3i nb = ijk;
        nb[axis] += side;
        if (nb[axis] < 0 || nb[axis] >= counts[axis]) continue;
        const std::int64_t j = cut.grid.index(location, nb);
        sparse.insert(j, dense[j]);
      }
  }
  EXPECT_LT(sparse.indices().size(), static_cast<size_t>(n) / 2);  // sparse indeed

  const GaussJacobiRefill refill(cut.grid, location);
  const auto object = [](std::int64_t, std::int64_t) { return 0.25; };
  refill.run(dense, valid_dense, invalid, refill.wedge_visibility(caster), object);
  refill.run(sparse, valid_sparse, invalid, refill.wedge_visibility(caster), object);
  for (const std::int64_t i : invalid) {
    ASSERT_EQ(valid_sparse[i], 1);
    ASSERT_EQ(sparse[i], dense[i]) << "sample " << i;
  }
  // clear() forgets every sample and leaves the grid's size.
  sparse.clear();
  EXPECT_TRUE(sparse.indices().empty());
  EXPECT_FALSE(sparse.contains(invalid.front()));
  EXPECT_EQ(sparse.size(), n);
}

}  // namespace
}  // namespace shellflow::geometry
