// §4.2's transfers on cut cells (issue #52, docs/cut-cells.md §2.8): each fragment of a face a
// level plate splits is a face sample of its own. A node beside the plate reads the fragments
// that hold it as a corner, so the film side's velocity reaches the nodes of the film's side
// (a face centre across the plate is invisible from them); a fragment takes its own corners'
// increments, so a shear across the plate reaches each side's fragments and no other.
#include <gtest/gtest.h>

#include <vector>

#include "grid_fluid_test_support.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/face_node_transfer.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

const grid::UniformGrid kGrid(Eigen::Vector3d::Zero(), 1.0 / 16, Eigen::Vector3i(8, 16, 8));
const double kDx = kGrid.dx();
const double kPlate = 5.82 * kDx;  // 0.32 of a cell above row 5's centres: row 5 is cut
// A face of family x or z in row 5 holds its lower corners (s = 0 along y, the family's first
// or second tangent axis) or its upper ones.
bool lower_fragment(int axis, const FaceFragment& fragment) {
  const int first = std::countr_zero(unsigned(fragment.corners));
  return CellParts::face_corner(axis, first).y() == 0;
}

/// The level plate across the tank, and the parts of the row it cuts.
test::CutShells plate_parts() {
  return test::CutShells(
      kGrid, {test::make_plate({0.25, kPlate, 0.25}, Eigen::Vector3d::UnitY(), 2.0, 9)});
}

// Faces still but the side fragments of row 5: 3 m/s below the plate, 5 m/s above it (the
// film's). An interior node at y = 6Δx, above the plate, takes the mean of its two row-5
// fragments above the plate and its two row-6 faces: (5 + 5 + 0 + 0)/4; at y = 5Δx, below it,
// (3 + 3 + 0 + 0)/4. Without the fragments the node above sees no row-5 face (their centres lie
// below the plate) and reads 0.
TEST(CutFaceTransfer, ANodeReadsTheFragmentsOfItsSideOfAPlate) {
  const test::CutShells plate = plate_parts();
  MacGrid mac(kGrid);
  FragmentVelocities fragments = plate.parts.still_fragments();
  for (const int a : {0, 2})
    for (const FaceSplit& split : plate.parts.split_faces(a)) {
      const auto list = plate.parts.fragments_of(a, split);
      for (size_t k = 0; k < list.size(); ++k) {
        fragments[a][split.first + k] = lower_fragment(a, list[k]) ? 3.0 : 5.0;
        if (plate.parts.joins_slots(list[k])) mac.face_velocity(a)[split.face] = 3.0;
      }
    }
  const FaceNodeTransfer transfer(kGrid);
  NodeFields nodes(kGrid, 300.0, false), plain(kGrid, 300.0, false);
  const CutFaces cut{&plate.parts, &fragments};
  transfer.faces_to_nodes(mac, nodes, plate.geometry, &plate.band, &cut);
  transfer.faces_to_nodes(mac, plain, plate.geometry, &plate.band);
  for (const int a : {0, 2})
    for (int k = 1; k < 8; ++k)
      for (int i = 1; i < 8; ++i) {
        const std::int64_t above = kGrid.index(Location::Node, i, 6, k);
        const std::int64_t below = kGrid.index(Location::Node, i, 5, k);
        EXPECT_DOUBLE_EQ(nodes.velocity(a)[above], 2.5) << "axis " << a;
        EXPECT_DOUBLE_EQ(nodes.velocity(a)[below], 1.5) << "axis " << a;
        EXPECT_DOUBLE_EQ(plain.velocity(a)[above], 0.0) << "axis " << a;
      }
}

// Node increments +1 m/s below the plate and −1 above it (a shear across it): each side
// fragment of row 5 takes its own corners' increment, the fragments below the plate +1 and
// those above −1, and the MAC face keeps the slots' (below, where the centres lie); the faces
// of rows 4 and 6 take +1 and −1.
TEST(CutFaceTransfer, AFragmentTakesItsOwnCornersIncrement) {
  const test::CutShells plate = plate_parts();
  MacGrid mac(kGrid);
  FragmentVelocities fragments = plate.parts.still_fragments();
  NodeFields u_star(kGrid, 300.0, false);
  std::array<std::vector<double>, 3> u_n;
  for (int a = 0; a < 3; ++a) {
    u_n[a].assign(u_star.velocity(a).size(), 0.0);
    for (std::int64_t v = 0; v < kGrid.size(Location::Node); ++v)
      u_star.velocity(a)[v] = kGrid.position(Location::Node, v).y() < kPlate ? 1.0 : -1.0;
  }
  const CutFaces cut{&plate.parts, &fragments};
  const std::array<std::vector<std::uint8_t>, 3> no_faces;
  FaceNodeTransfer transfer(kGrid);
  transfer.increments_to_faces(mac, u_star, u_n, {}, no_faces, plate.geometry, &plate.band,
                               DomainBoundary(), &cut);
  for (const int a : {0, 2}) {
    ASSERT_FALSE(plate.parts.split_faces(a).empty());
    for (const FaceSplit& split : plate.parts.split_faces(a)) {
      const auto list = plate.parts.fragments_of(a, split);
      ASSERT_EQ(list.size(), 2u);
      for (size_t k = 0; k < list.size(); ++k)
        EXPECT_EQ(fragments[a][split.first + k], lower_fragment(a, list[k]) ? 1.0 : -1.0);
      EXPECT_EQ(mac.face_velocity(a)[split.face], 1.0);
    }
    const Location loc = face_location(a);
    for (int k = 1; k < 7; ++k)
      for (int i = 1; i < 7; ++i) {
        EXPECT_EQ(mac.face_velocity(a)[kGrid.index(loc, i, 4, k)], 1.0);
        EXPECT_EQ(mac.face_velocity(a)[kGrid.index(loc, i, 6, k)], -1.0);
      }
  }
}

}  // namespace
}  // namespace shellflow::grid_fluid
