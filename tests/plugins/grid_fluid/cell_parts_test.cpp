// CellParts: the parts of the cells shells cut, and the fragments of their faces (issue #52,
// docs/cut-cells.md §2.1–2.2). Known answers from flat plates: each part's share of its cell and
// each fragment's share of its face follow from where the plate lies; plates within ε of a centre,
// a face or an edge; a plate remeshed finer; a fold whose pocket holds no corner.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grid_fluid_test_support.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/water/volume_fraction.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

// 8³ cells of Δx = 1/8 over the unit cube; ε as the solver's (1e-3 Δx).
const grid::UniformGrid kGrid(Eigen::Vector3d::Zero(), 1.0 / 8, Eigen::Vector3i(8, 8, 8));
const double kDx = kGrid.dx();
const double kEpsilon = 1e-3 * kDx;

/// The parts that plates (each wider than the domain) give.
test::CutShells parts_of(std::vector<sdk::ShellSurface> shells) {
  return test::CutShells(kGrid, std::move(shells));
}

sdk::ShellSurface level_plate(double y, int nodes = 9) {
  return test::make_plate({0.5, y, 0.5}, Eigen::Vector3d::UnitY(), 2.0, nodes);
}

// Corner masks of a cell's lower (y = 0) and upper (y = 1) corners: bit x + 2y + 4z.
constexpr std::uint8_t kLower = 0x33, kUpper = 0xCC;

/// The signed distance of a part's corners to a plane: all on one side (its sign), else 0.
int side_of(const CellPart& part, const Eigen::Vector3d& normal, const Eigen::Vector3d& point) {
  const Eigen::Vector3i ijk = kGrid.coordinates(Location::Cell, part.cell);
  int side = 0;
  for (int c = 0; c < 8; ++c) {
    if (!(part.corners >> c & 1u)) continue;
    const double d = normal.dot(
        kGrid.position(Location::Node, Eigen::Vector3i(ijk + CellParts::cell_corner(c))) - point);
    const int s = d > 0.0 ? 1 : -1;
    if (side != 0 && s != side) return 0;
    side = s;
  }
  return side;
}

/// The volume below the plane (n·x < n·point) that the cells and parts hold: whole cells by their
/// centre's side, cut cells by their parts' sides.
double volume_below(const CellParts& parts, const Eigen::Vector3d& normal,
                    const Eigen::Vector3d& point) {
  double below = 0.0;
  for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c) {
    const auto own = parts.parts_of(c);
    if (own.empty()) {
      below += normal.dot(kGrid.position(Location::Cell, c) - point) < 0.0 ? 1.0 : 0.0;
      continue;
    }
    for (const CellPart& part : own) {
      const int side = side_of(part, normal, point);
      EXPECT_NE(side, 0) << "a part with corners on both sides of the plate, cell " << c;
      if (side < 0) below += part.volume;
    }
  }
  return below * kDx * kDx * kDx;
}

// A level plate h of a cell above a plane of centres parts each cell of that row into the corners
// below it (½ + h of the cell) and above it (½ − h); the cells' side faces split alike, each
// fragment joining the two cells' parts on its side; the faces along y keep one fragment, whole.
TEST(CellParts, ALevelPlatePartsEachCellItCrossesByItsOffset) {
  for (const double h : {0.1, 0.32, 0.68, 0.9}) {
    const int row = h < 0.5 ? 3 : 4;
    const double offset = h < 0.5 ? h : h - 1.0;  // from the cut row's centres
    const auto found = parts_of({level_plate((3.5 + h) * kDx)});
    const CellParts& parts = found.parts;
    ASSERT_EQ(parts.parts().size(), 2u * 64u) << "h " << h;
    for (const CellPart& part : parts.parts()) {
      ASSERT_EQ(kGrid.coordinates(Location::Cell, part.cell).y(), row) << "h " << h;
      ASSERT_TRUE(part.corners == kLower || part.corners == kUpper);
      const double expected = part.corners == kLower ? 0.5 + offset : 0.5 - offset;
      EXPECT_NEAR(part.volume, expected, 1e-12) << "h " << h;  // both from exact planes
      EXPECT_EQ(part.holds_centre, (part.corners == kLower) == (offset > 0.0)) << "h " << h;
      EXPECT_EQ(part.slot, part.holds_centre) << "h " << h;
    }
    for (const int a : {0, 2}) {
      const Location loc = a == 0 ? Location::FaceX : Location::FaceZ;
      EXPECT_EQ(parts.split_faces(a).size(), 7u * 8u) << "axis " << a;  // the row's interior faces
      for (const FaceSplit& split : parts.split_faces(a)) {
        ASSERT_EQ(kGrid.coordinates(loc, split.face).y(), row);
        const auto fragments = parts.fragments_of(a, split);
        ASSERT_EQ(fragments.size(), 2u);
        for (const FaceFragment& fragment : fragments) {
          const bool lower =
              CellParts::face_corner(a, std::countr_zero(unsigned(fragment.corners))).y() == 0;
          EXPECT_NEAR(fragment.aperture, lower ? 0.5 + offset : 0.5 - offset, 1e-12);
          ASSERT_GE(fragment.minus, 0);
          ASSERT_GE(fragment.plus, 0);
          EXPECT_EQ(parts.parts()[fragment.minus].corners, lower ? kLower : kUpper);
          EXPECT_EQ(parts.parts()[fragment.plus].corners, lower ? kLower : kUpper);
        }
      }
    }
    for (const FaceSplit& split : parts.split_faces(1)) {
      const int y = kGrid.coordinates(Location::FaceY, split.face).y();
      ASSERT_TRUE(y == row || y == row + 1);
      const auto fragments = parts.fragments_of(1, split);
      ASSERT_EQ(fragments.size(), 1u);
      EXPECT_EQ(fragments[0].aperture, 1.0);
      const std::int32_t cut = y == row ? fragments[0].plus : fragments[0].minus;
      ASSERT_GE(cut, 0);
      EXPECT_EQ(parts.parts()[cut].corners, y == row ? kLower : kUpper);
      EXPECT_EQ(y == row ? fragments[0].minus : fragments[0].plus, -1);  // the whole cell
    }
  }
}

// A plate at a slant: every part lies on one side, the parts and whole cells below it hold the
// volume below it in the unit cube exactly, and each face's fragments share its square.
TEST(CellParts, ASlantedPlatesPartsHoldTheVolumeOnEachSideOfIt) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, 1.0, -0.2).normalized();
  const Eigen::Vector3d point(0.5, 0.47, 0.5);
  const auto found = parts_of({test::make_plate(point, normal, 3.0, 13)});
  const CellParts& parts = found.parts;
  EXPECT_GT(parts.parts().size(), 2u * 64u);
  const double exact = VolumeFraction::box_fraction_below(
      normal, normal.dot(point - Eigen::Vector3d::Constant(0.5)), Eigen::Vector3d::Constant(-0.5),
      Eigen::Vector3d::Constant(0.5));
  EXPECT_NEAR(volume_below(parts, normal, point), exact, 1e-12);
  for (int a = 0; a < 3; ++a)
    for (const FaceSplit& split : parts.split_faces(a)) {
      double sum = 0.0;
      for (const FaceFragment& fragment : parts.fragments_of(a, split)) sum += fragment.aperture;
      EXPECT_NEAR(sum, 1.0, 1e-12) << "axis " << a << " face " << split.face;
    }
}

// The same plate remeshed 25 times finer (triangles of about Δx/5) gives the same parts, shares
// and fragments to round-off: one plane holds the triangles near each cell either way.
TEST(CellParts, TrianglesSmallerThanACellGiveTheSameParts) {
  const double y = 3.82 * kDx;
  const auto coarse = parts_of({level_plate(y, 9)});
  const auto fine = parts_of({level_plate(y, 81)});
  ASSERT_EQ(coarse.parts.parts().size(), fine.parts.parts().size());
  for (size_t k = 0; k < coarse.parts.parts().size(); ++k) {
    const CellPart &p = coarse.parts.parts()[k], &q = fine.parts.parts()[k];
    EXPECT_EQ(p.cell, q.cell);
    EXPECT_EQ(p.corners, q.corners);
    EXPECT_NEAR(p.volume, q.volume, 1e-12);
  }
  for (int a = 0; a < 3; ++a) {
    ASSERT_EQ(coarse.parts.split_faces(a).size(), fine.parts.split_faces(a).size());
    for (size_t k = 0; k < coarse.parts.split_faces(a).size(); ++k) {
      const auto p = coarse.parts.fragments_of(a, coarse.parts.split_faces(a)[k]);
      const auto q = fine.parts.fragments_of(a, fine.parts.split_faces(a)[k]);
      ASSERT_EQ(p.size(), q.size());
      for (size_t j = 0; j < p.size(); ++j) EXPECT_NEAR(p[j].aperture, q[j].aperture, 1e-12);
    }
  }
}

// A plate within ε/2 of a plane of centres gives the parts of the same plate 10ε away: the centre
// is no sample; the shares move with the plate.
TEST(CellParts, APlateThroughTheCentresChangesNothingButTheShares) {
  const double centres = 3.5 * kDx;
  const auto near = parts_of({level_plate(centres + 0.25 * kEpsilon)});
  const auto away = parts_of({level_plate(centres + 10.0 * kEpsilon)});
  ASSERT_EQ(near.parts.parts().size(), 2u * 64u);
  ASSERT_EQ(near.parts.parts().size(), away.parts.parts().size());
  for (size_t k = 0; k < near.parts.parts().size(); ++k) {
    const CellPart &p = near.parts.parts()[k], &q = away.parts.parts()[k];
    EXPECT_EQ(p.cell, q.cell);
    EXPECT_EQ(p.corners, q.corners);
    const double moved = (p.corners == kLower ? 1.0 : -1.0) * (10.0 - 0.25) * kEpsilon / kDx;
    EXPECT_NEAR(q.volume - p.volume, moved, 1e-12);
  }
}

// A plate within ε/2 of a plane of faces puts their corners in its wedge: no cell is cut and the
// faces it lies in are closed. 10ε away, the cells below it keep a sliver of 10ε above it, which
// the faces in that plane join to the whole cells above.
TEST(CellParts, APlateInAFacesPlaneClosesItAndASliverAwayFromItIsAPart) {
  const double faces = 4.0 * kDx;
  const auto in_plane = parts_of({level_plate(faces - 0.25 * kEpsilon)});
  EXPECT_TRUE(in_plane.parts.parts().empty());
  ASSERT_EQ(in_plane.parts.split_faces(1).size(), 64u);
  for (const FaceSplit& split : in_plane.parts.split_faces(1)) {
    EXPECT_EQ(kGrid.coordinates(Location::FaceY, split.face).y(), 4);
    EXPECT_EQ(split.count, 0) << "a face in the plate's plane is closed";
  }
  const auto sliver = parts_of({level_plate(faces - 10.0 * kEpsilon)});
  ASSERT_EQ(sliver.parts.parts().size(), 2u * 64u);
  for (const CellPart& part : sliver.parts.parts()) {
    EXPECT_EQ(kGrid.coordinates(Location::Cell, part.cell).y(), 3);
    EXPECT_NEAR(part.volume,
                part.corners == kUpper ? 10.0 * kEpsilon / kDx : 1.0 - 10.0 * kEpsilon / kDx,
                1e-12);
  }
  for (const FaceSplit& split : sliver.parts.split_faces(1)) {
    if (kGrid.coordinates(Location::FaceY, split.face).y() != 4) continue;
    const auto fragments = sliver.parts.fragments_of(1, split);
    ASSERT_EQ(fragments.size(), 1u);
    ASSERT_GE(fragments[0].minus, 0);
    EXPECT_EQ(sliver.parts.parts()[fragments[0].minus].corners, kUpper);
    EXPECT_EQ(fragments[0].plus, -1);
  }
}

// A plate at 45° through a line of nodes (x = y = 4Δx, along z): the nodes on the line lie in its
// wedge; each cell it halves keeps its two free corners apart, half a cell each, and the volume on
// each side is exact.
TEST(CellParts, APlateThroughALineOfNodesHalvesTheCellsItCrosses) {
  const Eigen::Vector3d normal = Eigen::Vector3d(1.0, -1.0, 0.0).normalized();
  const Eigen::Vector3d point(4.0 * kDx, 4.0 * kDx, 0.5);
  const auto found = parts_of({test::make_plate(point, normal, 3.0, 13)});
  const CellParts& parts = found.parts;
  ASSERT_FALSE(parts.parts().empty());
  for (const CellPart& part : parts.parts()) {
    const Eigen::Vector3i ijk = kGrid.coordinates(Location::Cell, part.cell);
    EXPECT_EQ(ijk.x(), ijk.y()) << "only the cells on the diagonal are cut";
    EXPECT_EQ(std::popcount(unsigned(part.corners)), 2);
    EXPECT_NEAR(part.volume, 0.5, 1e-12);
  }
  EXPECT_EQ(parts.parts().size(), 2u * 8u * 8u);
  EXPECT_NEAR(volume_below(parts, normal, point), 0.5, 1e-12);
}

// Two level sheets 0.3Δx apart inside one row of cells (a fold): each cell keeps the corners below
// both and above both apart, 0.4 and 0.3 of a cell; the pocket between holds no corner and is no
// part. The shares come from lines split where they cross the sheets (no single plane).
TEST(CellParts, AFoldsPocketThinnerThanACellIsNoPart) {
  const auto found = parts_of({level_plate(3.4 * kDx), level_plate(3.7 * kDx)});
  const CellParts& parts = found.parts;
  ASSERT_EQ(parts.parts().size(), 2u * 64u);
  for (const CellPart& part : parts.parts()) {
    EXPECT_EQ(kGrid.coordinates(Location::Cell, part.cell).y(), 3);
    // Each line is split at the sheets exactly: round-off.
    EXPECT_NEAR(part.volume, part.corners == kLower ? 0.4 : 0.3, 1e-12);
    EXPECT_FALSE(part.holds_centre) << "the centre lies in the pocket";
    EXPECT_EQ(part.slot, part.corners == kLower) << "no part holds the centre: the largest";
  }
  for (const int a : {0, 2})
    for (const FaceSplit& split : parts.split_faces(a)) {
      const auto fragments = parts.fragments_of(a, split);
      ASSERT_EQ(fragments.size(), 2u);
      double sum = 0.0;
      for (const FaceFragment& fragment : fragments) sum += fragment.aperture;
      EXPECT_NEAR(sum, 0.7, 1e-12) << "the pocket's share of the face is closed";
    }
}

}  // namespace
}  // namespace shellflow::grid_fluid
