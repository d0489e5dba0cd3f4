// liquid_mesher: OpenVDB's mesh of a node or cell-centred level set. A sphere of water's
// area and volume converge at second order within the bound stated below; the mesh is
// closed and wound outward; velocities are the node field's trilinear interpolant; water
// against the box closes on its faces, on cell centres too, where a pool one cell deep is
// meshed; and no triangle crosses a thin plate that the nodal φ bridges.

#include "shellflow/liquid_writer/liquid_mesher.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh_checks.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::liquid_writer {
namespace {

using testing::NodeGrid;

/// The unit box with `cells` cells per axis, φ the signed distance to a sphere of radius
/// R about an off-grid centre, clamped to ±6Δx as grid_fluid clamps it.
NodeGrid sphere_phi(int cells, double radius) {
  const double dx = 1.0 / cells;
  NodeGrid phi(Eigen::Vector3d::Zero(), dx, {cells + 1, cells + 1, cells + 1}, 1);
  const Eigen::Vector3d centre(0.5 + 0.013, 0.5 - 0.021, 0.5 + 0.007);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    return std::clamp((x - centre).norm() - radius, -6.0 * dx, 6.0 * dx);
  });
  return phi;
}

struct SphereErrors {
  double area = 0.0, volume = 0.0;  ///< relative to the exact sphere's
};

SphereErrors sphere_errors(int cells, double radius) {
  const NodeGrid phi = sphere_phi(cells, radius);
  const LiquidMesh mesh = mesh_liquid(phi.view("phi"), nullptr, {}, {});
  EXPECT_TRUE(testing::closed_and_consistently_wound(mesh.triangles)) << cells << " cells";
  const double pi = std::numbers::pi;
  const double area = 4.0 * pi * radius * radius, volume = 4.0 / 3.0 * pi * std::pow(radius, 3);
  return {std::abs(mesh_area(mesh.positions, mesh.triangles) - area) / area,
          std::abs(mesh_volume(mesh.positions, mesh.triangles) - volume) / volume};
}

TEST(LiquidMesher, SphereAreaAndVolumeConvergeAtSecondOrder) {
  // The mesher's vertex in a cell is the mean of the cell's edge crossings. For an exact
  // signed distance the crossings lie on the sphere to O(Δx²/R), and the mean of points a
  // cell apart on a sphere lies inside it by about 0.4Δx²/R: area and volume come out
  // short by O((Δx/R)²) relative. Bounds: area 1.0 (Δx/R)², volume 1.5 (Δx/R)²; measured
  // at 16, 32 and 64 cells per unit (R = 0.3): constants 0.62 (area) and 1.13 (volume) at
  // every resolution, each error falling 4.0x per halving of Δx. Between 32 and 64 cells
  // each must fall at least 3.5x (order 1.8).
  const double radius = 0.3;
  constexpr double kAreaConstant = 1.0;
  constexpr double kVolumeConstant = 1.5;
  constexpr double kMinimumRatio = 3.5;
  SphereErrors previous;
  for (const int cells : {16, 32, 64}) {
    const SphereErrors e = sphere_errors(cells, radius);
    const double h = 1.0 / cells / radius;
    std::printf("cells %d: area error %.3e = %.2f (dx/R)^2, volume error %.3e = %.2f (dx/R)^2\n",
                cells, e.area, e.area / (h * h), e.volume, e.volume / (h * h));
    EXPECT_LT(e.area, kAreaConstant * h * h) << cells << " cells";
    EXPECT_LT(e.volume, kVolumeConstant * h * h) << cells << " cells";
    if (cells == 64) {
      EXPECT_LT(e.area, previous.area / kMinimumRatio);
      EXPECT_LT(e.volume, previous.volume / kMinimumRatio);
    }
    previous = e;
  }
}

TEST(LiquidMesher, MeshIsWoundOutwardWithTrilinearVelocities) {
  const NodeGrid phi = sphere_phi(24, 0.3);
  NodeGrid velocity(phi.origin, phi.dx, phi.dims, 3);
  // A linear field: its trilinear interpolant is itself, so each vertex's velocity is
  // exact up to round-off (1e-12 on values ~1).
  velocity.fill(0, [](const Eigen::Vector3d& x) { return 1.0 + 2.0 * x.x() - x.y(); });
  velocity.fill(1, [](const Eigen::Vector3d& x) { return 0.5 * x.z(); });
  velocity.fill(2, [](const Eigen::Vector3d& x) { return -x.x() + 3.0 * x.y(); });
  const sdk::FieldView velocity_view = velocity.view("velocity");
  const LiquidMesh mesh = mesh_liquid(phi.view("phi"), &velocity_view, {}, {});
  ASSERT_GT(mesh.positions.rows(), 500);
  EXPECT_GT(mesh_volume(mesh.positions, mesh.triangles), 0.0);  // counter-clockwise outside
  constexpr double kRoundOff = 1e-12;
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    const Eigen::Vector3d x = mesh.positions.row(v).transpose();
    const Eigen::Vector3d expected(1.0 + 2.0 * x.x() - x.y(), 0.5 * x.z(), -x.x() + 3.0 * x.y());
    ASSERT_NEAR((mesh.velocities.row(v).transpose() - expected).norm(), 0.0, kRoundOff);
  }
}

TEST(LiquidMesher, WaterAgainstTheBoxClosesOnItsFaces) {
  // A pool 0.4 deep filling the unit box (16^3): the mesh closes on the box's floor and
  // walls (the nodes there are clipped to air). Faces are flat (a crossing next to a
  // clipped node lies on it to τ = 1e-3Δx), but the vertex of a cell on one of the pool's
  // 12 edges (9.6 m in all) is the mean of crossings on two faces: each edge is bevelled,
  // about Δx²/2 per metre. Bound: 0.75Δx² per metre of edge, 7.2Δx² (measured 5.3Δx²: a
  // 5% loss at 16 cells, shrinking as Δx²); top within float round-off of 0.4 (the
  // crossing of a linear φ is exact away from the walls).
  const int cells = 16;
  const double dx = 1.0 / cells;
  NodeGrid phi(Eigen::Vector3d::Zero(), dx, {cells + 1, cells + 1, cells + 1}, 1);
  phi.fill(0, [](const Eigen::Vector3d& x) { return x.y() - 0.4; });
  const LiquidMesh mesh = mesh_liquid(phi.view("phi"), nullptr, {}, {});
  EXPECT_TRUE(testing::closed_and_consistently_wound(mesh.triangles));
  const double volume = mesh_volume(mesh.positions, mesh.triangles);
  std::printf("pool 0.4 deep: volume %.6f (error %.2f dx^2)\n", volume, (volume - 0.4) / (dx * dx));
  EXPECT_NEAR(volume, 0.4, 0.75 * dx * dx * 9.6);
  EXPECT_NEAR(mesh.positions.col(1).maxCoeff(), 0.4, 1e-6);  // float vertices: 2^-24 ≈ 6e-8 rel.
  EXPECT_GE(mesh.positions.minCoeff(), -1e-6);
  EXPECT_LE(mesh.positions.maxCoeff(), 1.0 + 1e-6);
}

/// A field on the cell centres of the box [0, size] in cells of dx, as GridFluid publishes
/// a cell-centred φ (origin the first centre, dims the cells).
NodeGrid cell_field(const Eigen::Vector3d& size, double dx, int components) {
  const std::array<int, 3> cells{static_cast<int>(std::lround(size.x() / dx)),
                                 static_cast<int>(std::lround(size.y() / dx)),
                                 static_cast<int>(std::lround(size.z() / dx))};
  NodeGrid field(Eigen::Vector3d::Constant(0.5 * dx), dx, cells, components);
  field.location = sdk::FieldView::Location::Cell;
  return field;
}

TEST(LiquidMesher, APoolOneCellDeepOnCellCentresIsMeshedAndClosesOnTheWalls) {
  // A pool 0.75 cells deep in a 16 x 8 x 12 box of cells (dx = 1/16), φ = y − depth on the
  // centres: all its water lies below the first centres' layer's top, in the cells that
  // clipping the outermost centres would make air (nothing would be meshed). With the
  // ghost layer the mesh is closed, its top at the depth (the crossing of a linear φ
  // between the first two centre layers: exact, to float vertices, 2^-24 ≈ 6e-8
  // relative), every vertex inside the box. Against a wall the vertex of a cell is the
  // mean of its edge crossings: one on the wall (the ghost's mirrored φ puts it there) and
  // one on the floor or the top, ¼dx from the wall. Hence a known volume: along each metre
  // of the pool's perimeter its side is the quadrilateral (1, 0) (¼, ¼) (¼, 5/8) (1, ¾) in
  // cells, short of the ¾ dx² strip by 21/64 dx²; the four corners' cells differ from
  // that by less than a cell's volume each (measured +0.51 dx³ for the four).
  const double dx = 1.0 / 16;
  const Eigen::Vector3d size(1.0, 0.5, 0.75);
  const double depth = 0.75 * dx;
  NodeGrid phi = cell_field(size, dx, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) { return x.y() - depth; });
  const LiquidMesh mesh = mesh_liquid(phi.view("phi"), nullptr, {}, {});
  ASSERT_GT(mesh.positions.rows(), 0);
  EXPECT_TRUE(testing::closed_and_consistently_wound(mesh.triangles));
  EXPECT_EQ(mesh.clipped_nodes, 0);  // only the ghosts are clipped, and they are air
  const double perimeter = 2.0 * (size.x() + size.z());
  const double expected = depth * size.x() * size.z() - 21.0 / 64.0 * dx * dx * perimeter;
  const double volume = mesh_volume(mesh.positions, mesh.triangles);
  std::printf("pool 0.75 dx deep: volume %.8f, expected %.8f (corners %+.3f dx^3)\n", volume,
              expected, (volume - expected) / std::pow(dx, 3));
  EXPECT_NEAR(volume, expected, 4.0 * std::pow(dx, 3));
  constexpr double kFloat = 1e-6;  // float vertices: 2^-24 ≈ 6e-8 relative, with room
  EXPECT_NEAR(mesh.positions.col(1).maxCoeff(), depth, kFloat);
  EXPECT_NEAR(mesh.positions.col(1).minCoeff(), 0.0, kFloat);  // on the floor
  // The sides: ¼ dx from each wall.
  for (int a : {0, 2}) {
    EXPECT_NEAR(mesh.positions.col(a).minCoeff(), 0.25 * dx, kFloat);
    EXPECT_NEAR(mesh.positions.col(a).maxCoeff(), size[a] - 0.25 * dx, kFloat);
  }
}

TEST(LiquidMesher, APoolOnCellCentresHasItsSidesOnTheWalls) {
  // The same box with a pool 2.75 cells deep: the cells against a wall whose edges meet
  // neither the floor nor the top (the rows centred 1 and 2 cells up) hold only crossings
  // on the wall, where the ghost's mirrored φ puts each (−φ_b and φ_b half a cell either
  // side: exactly halfway, to float vertices). Their vertices lie on the walls.
  const double dx = 1.0 / 16;
  const Eigen::Vector3d size(1.0, 0.5, 0.75);
  NodeGrid phi = cell_field(size, dx, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) { return x.y() - 2.75 * dx; });
  const LiquidMesh mesh = mesh_liquid(phi.view("phi"), nullptr, {}, {});
  EXPECT_TRUE(testing::closed_and_consistently_wound(mesh.triangles));
  constexpr double kFloat = 1e-6;  // float vertices: 2^-24 ≈ 6e-8 relative, with room
  int on_walls = 0;
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    const Eigen::Vector3d x = mesh.positions.row(v).transpose();
    if (x.y() < 0.75 * dx || x.y() > 2.25 * dx) continue;  // the rows against floor and top
    const bool corner = std::min(x.z(), size.z() - x.z()) < 0.5 * dx;
    if (corner) continue;
    const double wall_distance = std::min(x.x(), size.x() - x.x());
    if (wall_distance < 0.5 * dx) {
      EXPECT_NEAR(wall_distance, 0.0, kFloat) << x.transpose() / dx;
      ++on_walls;
    }
  }
  // Rows 1 and 2 on both x walls, each between the 12 centres along z: 11 vertices.
  EXPECT_EQ(on_walls, 2 * 2 * 11);
  EXPECT_NEAR(mesh.positions.col(1).maxCoeff(), 2.75 * dx, kFloat);
}

TEST(LiquidMesher, ACellFieldsVerticesTakeTheNodeVelocityAtTheirPositions) {
  // φ on cell centres, the velocity on the nodes (other dims and origin, as GridFluid
  // publishes them): a linear field, whose trilinear interpolant is itself, so each
  // vertex's velocity is exact up to round-off (1e-12 on values ~1).
  const double dx = 1.0 / 24;
  NodeGrid phi = cell_field(Eigen::Vector3d::Ones(), dx, 1);
  const Eigen::Vector3d centre(0.5 + 0.013, 0.5 - 0.021, 0.5 + 0.007);
  phi.fill(0, [&](const Eigen::Vector3d& x) { return (x - centre).norm() - 0.3; });
  NodeGrid velocity(Eigen::Vector3d::Zero(), dx, {25, 25, 25}, 3);
  velocity.fill(0, [](const Eigen::Vector3d& x) { return 1.0 + 2.0 * x.x() - x.y(); });
  velocity.fill(1, [](const Eigen::Vector3d& x) { return 0.5 * x.z(); });
  velocity.fill(2, [](const Eigen::Vector3d& x) { return -x.x() + 3.0 * x.y(); });
  const sdk::FieldView velocity_view = velocity.view("velocity");
  const LiquidMesh mesh = mesh_liquid(phi.view("phi"), &velocity_view, {}, {});
  ASSERT_GT(mesh.positions.rows(), 500);
  constexpr double kRoundOff = 1e-12;
  for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
    const Eigen::Vector3d x = mesh.positions.row(v).transpose();
    const Eigen::Vector3d expected(1.0 + 2.0 * x.x() - x.y(), 0.5 * x.z(), -x.x() + 3.0 * x.y());
    ASSERT_NEAR((mesh.velocities.row(v).transpose() - expected).norm(), 0.0, kRoundOff);
  }
}

TEST(LiquidMesher, SmoothingKeepsAPoolOnCellCentresAgainstTheWalls) {
  // A pool 3.3 cells deep filling a 16 x 8 x 12 box of cells, φ clamped to ±6 dx as the
  // fluid clamps it. A plane is a fixed point of a Gaussian filter, so 5 passes leave the
  // pool as it was but for the filter's renormalisation and float storage (measured: the
  // top rises 0.005 cells a pass, the volume +0.13 %); bound 0.5 %. With too few ghost
  // layers the air beyond them eats the water along the walls: with one, 1.7 % in one pass
  // and all of it in 5; with 3 a pass, 2.2 % in 5.
  const double dx = 1.0 / 16;
  NodeGrid phi = cell_field(Eigen::Vector3d(1.0, 0.5, 0.75), dx, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    return std::clamp(x.y() - 3.3 * dx, -6.0 * dx, 6.0 * dx);
  });
  const LiquidMesh sharp = mesh_liquid(phi.view("phi"), nullptr, {}, {});
  LiquidMeshOptions options;
  options.smoothing_iterations = 5;
  const LiquidMesh smooth = mesh_liquid(phi.view("phi"), nullptr, {}, options);
  EXPECT_TRUE(testing::closed_and_consistently_wound(smooth.triangles));
  const double v_sharp = mesh_volume(sharp.positions, sharp.triangles);
  const double v_smooth = mesh_volume(smooth.positions, smooth.triangles);
  std::printf("pool 3.3 dx deep: volume %.6f sharp, %.6f after 5 passes (%+.2f%%)\n", v_sharp,
              v_smooth, 100.0 * (v_smooth / v_sharp - 1.0));
  EXPECT_NEAR(v_smooth, v_sharp, 5e-3 * v_sharp);
  constexpr double kFloat = 1e-6;  // float vertices: 2^-24 ≈ 6e-8 relative, with room
  EXPECT_NEAR(smooth.positions.col(0).minCoeff(), 0.0, kFloat);  // still on the walls
  EXPECT_NEAR(smooth.positions.col(0).maxCoeff(), 1.0, kFloat);
}

/// A square plate x = plate_x spanning the unit box and beyond.
sdk::ShellSurface plate_at(double plate_x) {
  auto grid = geometry::make_grid(1.2, 1.2, 9, 9, geometry::GridPattern::Alternating);
  sdk::ShellSurface s;
  s.name = "plate";
  s.positions.resize(grid.positions.rows(), 3);
  for (Eigen::Index i = 0; i < grid.positions.rows(); ++i)  // the grid's (u, v, 0) → (x, v, u)
    s.positions.row(i) << plate_x, 0.5 + grid.positions(i, 1), 0.5 + grid.positions(i, 0);
  s.velocities = sdk::Positions::Zero(s.positions.rows(), 3);
  s.triangles = std::make_shared<const sdk::Triangles>(grid.triangles);
  return s;
}

TEST(LiquidMesher, NoTriangleCrossesAThinPlateTheNodalLevelSetBridges) {
  // Water x < 0.5 + 0.6Δx behind a plate at x = 0.5 + Δx/3 (between node planes): the
  // node at 0.5 is wet (φ = −0.6Δx), the one at 0.5 + Δx dry (φ = 0.4Δx), and the linear
  // crossing at 0.5 + 0.6Δx lies beyond the plate. Meshed alone, φ bridges the plate;
  // with the plate, no triangle meets it and every vertex is on the wet side, at any
  // adaptivity (exact: counts).
  const int cells = 16;
  const double dx = 1.0 / cells;
  const double plate_x = 0.5 + dx / 3.0;
  NodeGrid phi(Eigen::Vector3d::Zero(), dx, {cells + 1, cells + 1, cells + 1}, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    return std::max(x.x() - (0.5 + 0.6 * dx), x.y() - 0.7);  // a box of water 0.7 deep
  });
  const sdk::ShellSurface plate = plate_at(plate_x);
  const LiquidMesh bridging = mesh_liquid(phi.view("phi"), nullptr, {}, {});
  EXPECT_GT(testing::triangles_meeting_shell(bridging.positions, bridging.triangles, plate), 0);
  for (const double adaptivity : {0.0, 0.5, 1.0}) {
    LiquidMeshOptions options;
    options.adaptivity = adaptivity;
    const std::vector<sdk::ShellSurface> shells{plate};
    const LiquidMesh mesh = mesh_liquid(phi.view("phi"), nullptr, shells, options);
    ASSERT_GT(mesh.triangles.rows(), 100) << "adaptivity " << adaptivity;
    EXPECT_EQ(testing::triangles_meeting_shell(mesh.positions, mesh.triangles, plate), 0)
        << "adaptivity " << adaptivity;
    EXPECT_LT(mesh.positions.col(0).maxCoeff(), plate_x) << "adaptivity " << adaptivity;
    EXPECT_TRUE(testing::closed_and_consistently_wound(mesh.triangles));
    EXPECT_GT(mesh.clipped_nodes, 0);
  }
}

TEST(LiquidMesher, SmoothingRoundsACubesCornersAndStillNeverCrossesAPlate) {
  // A cube of water [0.3, 0.7]^3 at 32 cells per unit, its exact signed distance: the
  // unsmoothed mesh reaches within a cell of each corner; after 4 Gaussian passes its corners
  // are rounded, the nearest vertex at least a further half cell away (measured: 0.46Δx
  // sharp, 4.6Δx smoothed), while the faces move in by less than half a cell (measured
  // 0.39Δx: the filter also shrinks a 13-cell cube as a whole). With a plate through the
  // cube at x = 0.5 + Δx/3, the smoothed mesh still never meets the plate.
  const int cells = 32;
  const double dx = 1.0 / cells;
  NodeGrid phi(Eigen::Vector3d::Zero(), dx, {cells + 1, cells + 1, cells + 1}, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d q = (x - Eigen::Vector3d::Constant(0.5)).cwiseAbs() -
                              Eigen::Vector3d::Constant(0.2);
    return std::clamp(q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0), -6.0 * dx, 6.0 * dx);
  });
  const Eigen::Vector3d corner = Eigen::Vector3d::Constant(0.7);
  const auto nearest_to_corner = [&](const LiquidMesh& mesh) {
    return (mesh.positions.rowwise() - corner.transpose()).rowwise().norm().minCoeff();
  };
  LiquidMeshOptions smooth;
  smooth.smoothing_iterations = 4;
  const LiquidMesh sharp = mesh_liquid(phi.view("phi"), nullptr, {}, {});
  const LiquidMesh rounded = mesh_liquid(phi.view("phi"), nullptr, {}, smooth);
  std::printf("corner: nearest vertex %.3f dx sharp, %.3f dx smoothed\n",
              nearest_to_corner(sharp) / dx, nearest_to_corner(rounded) / dx);
  EXPECT_LT(nearest_to_corner(sharp), dx);
  EXPECT_GT(nearest_to_corner(rounded), nearest_to_corner(sharp) + 0.5 * dx);
  EXPECT_TRUE(testing::closed_and_consistently_wound(rounded.triangles));
  EXPECT_NEAR(rounded.positions.col(1).maxCoeff(), 0.7, 0.5 * dx);  // the top face

  const sdk::ShellSurface plate = plate_at(0.5 + dx / 3.0);
  const std::vector<sdk::ShellSurface> shells{plate};
  const LiquidMesh cut = mesh_liquid(phi.view("phi"), nullptr, shells, smooth);
  EXPECT_EQ(testing::triangles_meeting_shell(cut.positions, cut.triangles, plate), 0);
  EXPECT_GT(cut.clipped_nodes, 0);
}

TEST(LiquidMesher, RejectsAFieldThatIsNotANodeLevelSet) {
  NodeGrid phi(Eigen::Vector3d::Zero(), 0.0, {4, 4, 4}, 1);  // dx = 0
  EXPECT_THROW(mesh_liquid(phi.view("phi"), nullptr, {}, {}), Error);
}

}  // namespace
}  // namespace shellflow::liquid_writer
