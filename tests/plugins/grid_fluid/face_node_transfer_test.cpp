// §4.2's transfer of face velocities to the nodes: the row kernel used away from shells
// against the per-node path the shell band takes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "grid_fluid_test_support.hpp"
#include "shellflow/geometry/aabb.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/face_node_transfer.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

/// A plate 10 m away, which no ray meets, and a shell band over the whole grid: every
/// node and face takes the per-node (per-face) path, where every face (node) is seen.
struct FarShell {
  explicit FarShell(const grid::UniformGrid& grid)
      : plates{test::make_plate({10.0, 10.0, 10.0}, Eigen::Vector3d::UnitY(), 0.5, 3)},
        shells(plates, 1e-6),
        band(grid) {
    const geometry::Aabb everything(grid.origin() - Eigen::Vector3d::Ones(),
                                    grid.upper() + Eigen::Vector3d::Ones());
    band.add_boxes(std::span<const geometry::Aabb>(&everything, 1), 0.0);
  }
  std::vector<sdk::ShellSurface> plates;
  ShellGeometry shells;
  geometry::ShellBand band;
};

class RowsAgainstNodes : public testing::TestWithParam<Eigen::Vector3i> {};

TEST_P(RowsAgainstNodes, EveryNodeTakesTheMeanOfTheFacesAboutIt) {
  // Random face velocities on a box of cells (thin axes included: one cell across). The
  // row kernel must give every node the mean of the up to four faces of each family
  // about it, as the per-node path does where a shell lies so far off that every face
  // is seen, bit for bit: a run resumed from a checkpoint labels another shell band than
  // the run it resumes, so a node near the band's edge takes the other path
  // (GridFluidSmoke.SaveRestoreIsBitExact failed when the rows summed in another order).
  const Eigen::Vector3i cells = GetParam();
  const grid::UniformGrid grid(Eigen::Vector3d(0.2, -0.1, 0.3), 0.1, cells);
  MacGrid mac(grid);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  for (int a = 0; a < 3; ++a)
    for (double& u : mac.face_velocity(a)) u = value(random);
  const FaceNodeTransfer transfer(grid);
  NodeFields rows(grid, 300.0, false), per_node(grid, 300.0, false);
  transfer.faces_to_nodes(mac, rows, ShellGeometry(), nullptr);

  const FarShell far(grid);
  ASSERT_EQ(static_cast<std::int64_t>(far.band.samples(Location::Node).size()),
            grid.size(Location::Node));
  transfer.faces_to_nodes(mac, per_node, far.shells, &far.band);

  for (int a = 0; a < 3; ++a)
    for (std::int64_t i = 0; i < grid.size(Location::Node); ++i)
      ASSERT_EQ(rows.velocity(a)[i], per_node.velocity(a)[i])
          << "axis " << a << " node " << grid.coordinates(Location::Node, i).transpose();
  // And one node by hand: an interior node's x velocity is the mean of its four x-faces.
  if ((cells.array() >= 2).all()) {
    const Eigen::Vector3i node(1, 1, 1);
    double sum = 0.0;
    for (int dj = -1; dj <= 0; ++dj)
      for (int dk = -1; dk <= 0; ++dk)
        sum += mac.face_velocity(0)[grid.index(Location::FaceX, node + Eigen::Vector3i(0, dj, dk))];
    EXPECT_NEAR(rows.velocity(0)[grid.index(Location::Node, node)], 0.25 * sum, 1e-15 * 8.0);
  }
}

TEST_P(RowsAgainstNodes, EveryFaceTakesTheMeanIncrementOfItsNodes) {
  // §4.2's increments back to the faces: the row path away from shells against the
  // per-face path the band takes, with a far plate and a band over the whole grid, bit
  // for bit (as above); the walls' faces and an inflow side are left alone by both.
  const Eigen::Vector3i cells = GetParam();
  const grid::UniformGrid grid(Eigen::Vector3d(0.2, -0.1, 0.3), 0.1, cells);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  MacGrid start(grid);
  for (int a = 0; a < 3; ++a)
    for (double& u : start.face_velocity(a)) u = value(random);
  NodeFields u_star(grid, 300.0, false);
  std::array<std::vector<double>, 3> u_n;
  for (int a = 0; a < 3; ++a) {
    for (double& u : u_star.velocity(a)) u = value(random);
    u_n[a].resize(u_star.velocity(a).size());
    for (double& u : u_n[a]) u = value(random);
  }
  const nlohmann::json sides = {{"x_max", {{"type", "open"}}},
                                {"y_min", {{"type", "inflow"}, {"velocity", {0, 1, 0}}}}};
  const DomainBoundary boundary(sides, "/boundary");
  const std::array<std::vector<std::uint8_t>, 3> no_faces;
  FaceNodeTransfer transfer(grid);
  MacGrid rows = start;
  transfer.increments_to_faces(rows, u_star, u_n, {}, no_faces, ShellGeometry(), nullptr,
                               boundary);
  const FarShell far(grid);
  MacGrid per_face = start;
  transfer.increments_to_faces(per_face, u_star, u_n, {}, no_faces, far.shells, &far.band,
                               boundary);
  int changed = 0;
  for (int a = 0; a < 3; ++a)
    for (size_t f = 0; f < start.face_velocity(a).size(); ++f) {
      ASSERT_EQ(rows.face_velocity(a)[f], per_face.face_velocity(a)[f]) << "axis " << a;
      changed += rows.face_velocity(a)[f] != start.face_velocity(a)[f];
    }
  // Every face but those on the five fixed sides moved (x_max is open).
  int fixed = 0;
  for (int a = 0; a < 3; ++a) {
    const Location loc = face_location(a);
    for (std::int64_t f = 0; f < grid.size(loc); ++f) {
      const Eigen::Vector3i ijk = grid.coordinates(loc, f);
      fixed += (ijk[a] == 0) || (ijk[a] == cells[a] && a != 0);
    }
  }
  int total = 0;
  for (int a = 0; a < 3; ++a) total += static_cast<int>(start.face_velocity(a).size());
  EXPECT_EQ(changed, total - fixed);
}

INSTANTIATE_TEST_SUITE_P(Boxes, RowsAgainstNodes,
                         testing::Values(Eigen::Vector3i(5, 3, 4), Eigen::Vector3i(1, 4, 3),
                                         Eigen::Vector3i(4, 1, 2), Eigen::Vector3i(3, 2, 1),
                                         Eigen::Vector3i(1, 1, 1)));

}  // namespace
}  // namespace shellflow::grid_fluid
