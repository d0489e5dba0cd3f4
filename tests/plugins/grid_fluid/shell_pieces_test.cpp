// ShellPieces (issue #52): the shells' triangles clipped into the cells they cut into parts, and
// the flux of the shells' motion out of each part. Known answers from flat plates: a plate
// across the domain has a piece of area Δx² in each cell it cuts, the part above it on its
// normal's side; a plate translating at V sweeps the part behind it at A V·n and the part ahead
// at −A V·n, so that each cell's flux sums to nothing.
#include <gtest/gtest.h>

#include <bit>
#include <vector>

#include "grid_fluid_test_support.hpp"
#include "shellflow/grid_fluid/mac/shell_pieces.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

// 8³ cells of Δx = 1/8 over the unit cube.
const grid::UniformGrid kGrid(Eigen::Vector3d::Zero(), 1.0 / 8, Eigen::Vector3i(8, 8, 8));

constexpr std::uint8_t kLower = 0x33, kUpper = 0xCC;  // a cell's y = 0 and y = 1 corners

TEST(ShellPieces, ALevelPlateAcrossTheDomainHasAPieceOfACellsFaceInEachCutCell) {
  for (const double offset : {0.1, 0.32, 0.68, 0.9}) {
    const double y = (3.5 + offset) * kGrid.dx();
    test::CutShells cut(kGrid, {test::make_plate({0.5, y, 0.5}, Eigen::Vector3d::UnitY(), 2.0, 9)});
    const auto pieces = shell_pieces(cut.geometry, kGrid, cut.parts);
    std::vector<double> area(kGrid.size(Location::Cell), 0.0);
    for (const ShellPiece& piece : pieces) {
      area[piece.cell] += piece.area;
      ASSERT_GE(piece.front, 0);
      ASSERT_GE(piece.back, 0);
      EXPECT_EQ(cut.parts.parts()[piece.front].cell, piece.cell);
      EXPECT_EQ(cut.parts.parts()[piece.front].corners, kUpper) << "offset " << offset;
      EXPECT_EQ(cut.parts.parts()[piece.back].corners, kLower) << "offset " << offset;
    }
    int cut_cells = 0;
    for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c) {
      if (cut.parts.parts_of(c).empty()) {
        EXPECT_EQ(area[c], 0.0);
        continue;
      }
      ++cut_cells;
      EXPECT_NEAR(area[c], 1.0, 1e-12) << "offset " << offset;  // the plate's clipped pieces
    }
    EXPECT_EQ(cut_cells, 64);
  }
}

TEST(ShellPieces, ATranslatingPlateSweepsThePartBehindItAndFillsNoCell) {
  // A plate tilted in every axis, moving at V: each part's flux along each axis is the area
  // it bounds times V_a n_a, signed by its side; a cell's parts' fluxes cancel.
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, 1.0, -0.2).normalized();
  auto plate = test::make_plate({0.5, 0.47, 0.5}, normal, 0.6, 7);
  const Eigen::Vector3d velocity(0.3, 0.7, -0.2);
  for (Eigen::Index i = 0; i < plate.velocities.rows(); ++i)
    plate.velocities.row(i) = velocity.transpose();
  test::CutShells cut(kGrid, {plate});
  const auto pieces = shell_pieces(cut.geometry, kGrid, cut.parts);
  ASSERT_FALSE(pieces.empty());
  const auto flux = shell_flux(cut.geometry, pieces, cut.parts.parts().size());
  // Per cut cell: its parts' fluxes cancel (the plate only moves water within it), and the
  // part ahead of the plate loses, along each axis, the plate's area there times V_a n_a.
  std::vector<double> area(kGrid.size(Location::Cell), 0.0);
  for (const ShellPiece& piece : pieces) {
    EXPECT_NEAR(piece.normal.dot(normal), 1.0, 1e-12);  // the plate's triangles face one way
    area[piece.cell] += piece.area;
  }
  for (std::int64_t c = 0; c < kGrid.size(Location::Cell); ++c) {
    const auto own = cut.parts.parts_of(c);
    if (own.empty()) continue;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const CellPart& part : own) sum += flux[&part - cut.parts.parts().data()];
    EXPECT_NEAR(sum.norm(), 0.0, 1e-12);
  }
  for (const ShellPiece& piece : pieces) {
    const Eigen::Vector3d ahead = -area[piece.cell] * velocity.cwiseProduct(normal);
    EXPECT_NEAR((flux[piece.front] - ahead).norm(), 0.0, 1e-12);
  }
  // The part on the normal's side of each piece lies ahead of the plate.
  for (const ShellPiece& piece : pieces) {
    ASSERT_GE(piece.front, 0);
    const CellPart& front = cut.parts.parts()[piece.front];
    const Eigen::Vector3i ijk = kGrid.coordinates(Location::Cell, front.cell);
    const int c = std::countr_zero(unsigned(front.corners));
    const Eigen::Vector3d corner =
        kGrid.position(Location::Node, Eigen::Vector3i(ijk + CellParts::cell_corner(c)));
    EXPECT_GT(piece.normal.dot(corner - Eigen::Vector3d(0.5, 0.47, 0.5)), 0.0);
  }
}

}  // namespace
}  // namespace shellflow::grid_fluid
