#include "shellflow/liquid_writer/liquid_mesher.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "shellflow/liquid_writer/shell_cells.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/vdb_writer/vdb_file.hpp"

namespace shellflow::liquid_writer {

namespace {

/// τ / Δx: the value, in cells, of a node made air (see liquid_mesher.hpp).
constexpr double kClippedValue = 1e-3;
/// OpenVDB's usual narrow-band half-width (LEVEL_SET_HALF_WIDTH) [voxels].
constexpr double kHalfWidth = 3.0;
/// Just inside the band (float's 2^-24 with room): a ghost there is an active voxel whose
/// crossing with a deep inner one (−kHalfWidth) lies halfway, on the wall.
constexpr double kInsideBand = kHalfWidth * (1.0 - 1e-6);
/// Cells about a touched cell kept from merging when adaptive [cells].
constexpr int kUnmergedRing = 2;
/// Ghost layers about a cell field in a smoothing pass: a pass filters and renormalises
/// (OpenVDB's LevelSetTracker), which reaches beyond the filter's 1-voxel radius
/// (liquid_mesher_test: a pool against the walls, smoothed).
constexpr int kSmoothingGhostLayers = 5;

size_t node_index(const std::array<int, 3>& dims, int i, int j, int k) {
  return static_cast<size_t>(i) +
         static_cast<size_t>(dims[0]) * (static_cast<size_t>(j) + static_cast<size_t>(dims[1]) * k);
}

void check_fields(const sdk::FieldView& phi, const sdk::FieldView* velocity) {
  if (phi.components != 1 || phi.data[0] == nullptr || !(phi.dx > 0.0) || phi.dims[0] < 1 ||
      phi.dims[1] < 1 || phi.dims[2] < 1)
    throw Error("liquid_writer: the fluid's level set \"" + phi.name +
                "\" is not a non-empty one-component grid with dx > 0");
  if (velocity == nullptr) return;
  const bool components = velocity->components == 3 && velocity->data[0] != nullptr &&
                          velocity->data[1] != nullptr && velocity->data[2] != nullptr &&
                          velocity->dx > 0.0 && velocity->dims[0] >= 1 && velocity->dims[1] >= 1 &&
                          velocity->dims[2] >= 1;
  if (phi.location == sdk::FieldView::Location::Cell) {
    if (!components)
      throw Error(
          "liquid_writer: the fluid's velocity is not a non-empty three-component grid with "
          "dx > 0");
    return;
  }
  if (!components || velocity->dims != phi.dims || velocity->dx != phi.dx ||
      !velocity->origin.isApprox(phi.origin))
    throw Error(
        "liquid_writer: the fluid's velocity is not a three-component field on the "
        "level set's nodes");
}

/// Trilinear value of component c of a node field at x, coordinates clamped to the box.
double trilinear(const sdk::FieldView& field, int c, const Eigen::Vector3d& x) {
  int base[3];
  double w[3];
  for (int a = 0; a < 3; ++a) {
    const double f = std::clamp((x[a] - field.origin[a]) / field.dx, 0.0,
                                static_cast<double>(field.dims[a] - 1));
    base[a] = std::min(static_cast<int>(f), std::max(field.dims[a] - 2, 0));
    w[a] = field.dims[a] > 1 ? f - base[a] : 0.0;
  }
  double value = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
    const double weight =
        (di ? w[0] : 1.0 - w[0]) * (dj ? w[1] : 1.0 - w[1]) * (dk ? w[2] : 1.0 - w[2]);
    if (weight == 0.0) continue;
    value +=
        weight * field.data[c][node_index(field.dims, base[0] + di, base[1] + dj, base[2] + dk)];
  }
  return value;
}

/// ψ as a narrow-band level set (Museth 2013): voxel (i,j,k) is sample (i,j,k) of
/// `lattice`; |ψ| below the half-width active, deeper water inactive at −background, the
/// rest air.
openvdb::FloatGrid::Ptr level_set_grid(const std::vector<double>& psi, const NodeBox& lattice) {
  const double dx = lattice.dx;
  const float background = static_cast<float>(kHalfWidth * dx);
  auto grid = openvdb::FloatGrid::create(background);
  auto transform = openvdb::math::Transform::createLinearTransform(dx);
  transform->postTranslate(
      openvdb::Vec3d(lattice.origin.x(), lattice.origin.y(), lattice.origin.z()));
  grid->setTransform(transform);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  auto accessor = grid->getAccessor();
  const auto& dims = lattice.dims;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const float value = static_cast<float>(psi[node_index(dims, i, j, k)]);
        if (std::abs(value) < background)
          accessor.setValueOn(openvdb::Coord(i, j, k), value);
        else if (value < 0.0f)
          accessor.setValueOff(openvdb::Coord(i, j, k), -background);
      }
  openvdb::tools::prune(grid->tree());
  return grid;
}

/// φ after `iterations` Gaussian passes (OpenVDB LevelSetFilter, which keeps it a signed
/// distance), read back at the samples.
std::vector<double> smoothed(std::vector<double> psi, const NodeBox& lattice, int iterations) {
  auto grid = level_set_grid(psi, lattice);
  openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
  for (int n = 0; n < iterations; ++n) filter.gaussian(1);
  auto accessor = grid->getConstAccessor();
  const auto& dims = lattice.dims;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        psi[node_index(dims, i, j, k)] = accessor.getValue(openvdb::Coord(i, j, k));
  return psi;
}

/// A cell field's samples inside `layers` ghost layers (dims + 2 layers per axis), each
/// ghost the value of its nearest sample: φ continued constant beyond the outermost
/// centres, as the simulation continues it.
std::vector<double> grown(const double* phi, const std::array<int, 3>& dims, int layers) {
  const std::array<int, 3> n{dims[0] + 2 * layers, dims[1] + 2 * layers, dims[2] + 2 * layers};
  std::vector<double> psi(static_cast<size_t>(n[0]) * n[1] * n[2]);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        psi[node_index(n, i, j, k)] = phi[node_index(dims, std::clamp(i - layers, 0, dims[0] - 1),
                                                     std::clamp(j - layers, 0, dims[1] - 1),
                                                     std::clamp(k - layers, 0, dims[2] - 1))];
  return psi;
}

/// The block of `psi` (a lattice of `dims`) less `margin` samples on every side.
std::vector<double> cropped(const std::vector<double>& psi, const std::array<int, 3>& dims,
                            int margin) {
  const std::array<int, 3> n{dims[0] - 2 * margin, dims[1] - 2 * margin, dims[2] - 2 * margin};
  std::vector<double> out(static_cast<size_t>(n[0]) * n[1] * n[2]);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        out[node_index(n, i, j, k)] = psi[node_index(dims, i + margin, j + margin, k + margin)];
  return out;
}

/// The samples a cell field is meshed on: its centres, smoothed by `smoothing` passes,
/// inside one layer of ghosts max(−φ_b, τ) (see liquid_mesher.hpp).
std::vector<double> cell_samples(const sdk::FieldView& phi, int smoothing, double tau) {
  std::vector<double> psi;
  const std::array<int, 3> n{phi.dims[0] + 2, phi.dims[1] + 2, phi.dims[2] + 2};
  if (smoothing > 0) {
    // Each pass sees φ continued constant beyond the centres, as the simulation does,
    // deep enough that what it assumes beyond the samples (air) never reaches them.
    constexpr int layers = kSmoothingGhostLayers;
    NodeBox wide{phi.origin.array() - layers * phi.dx, phi.dx, phi.dims};
    for (int a = 0; a < 3; ++a) wide.dims[a] += 2 * layers;
    std::vector<double> centres(
        phi.data[0], phi.data[0] + static_cast<size_t>(phi.dims[0]) * phi.dims[1] * phi.dims[2]);
    for (int pass = 0; pass < smoothing; ++pass)
      centres =
          cropped(smoothed(grown(centres.data(), phi.dims, layers), wide, 1), wide.dims, layers);
    psi = grown(centres.data(), phi.dims, 1);
  } else {
    psi = grown(phi.data[0], phi.dims, 1);
  }
  // The ghosts: a wet first cell's φ mirrored, a dry one's air; inside the narrow band, or
  // the mesher (which meshes about active voxels) left the wall under deep water open.
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        if (i > 0 && j > 0 && k > 0 && i < n[0] - 1 && j < n[1] - 1 && k < n[2] - 1) continue;
        const double b = psi[node_index(n, std::clamp(i, 1, n[0] - 2), std::clamp(j, 1, n[1] - 2),
                                        std::clamp(k, 1, n[2] - 2))];
        psi[node_index(n, i, j, k)] = std::min(std::max(-b, tau), kInsideBand * phi.dx);
      }
  return psi;
}

}  // namespace

LiquidMesh mesh_liquid(const sdk::FieldView& phi, const sdk::FieldView* velocity,
                       sdk::ShellSet shells, const LiquidMeshOptions& options) {
  check_fields(phi, velocity);
  vdb_writer::initialize_openvdb_once();
  LiquidMesh mesh;
  const double tau = kClippedValue * phi.dx;
  // The lattice meshed: a node field's own samples, or a cell field's inside one ghost
  // layer (see liquid_mesher.hpp). Its outermost samples are air.
  const bool cells = phi.location == sdk::FieldView::Location::Cell;
  NodeBox lattice{phi.origin, phi.dx, phi.dims};
  std::vector<double> psi;
  if (cells) {
    lattice.origin.array() -= phi.dx;
    for (int a = 0; a < 3; ++a) lattice.dims[a] += 2;
    psi = cell_samples(phi, options.smoothing_iterations, tau);
  } else {
    psi.assign(phi.data[0],
               phi.data[0] + static_cast<size_t>(phi.dims[0]) * phi.dims[1] * phi.dims[2]);
    if (options.smoothing_iterations > 0)
      psi = smoothed(std::move(psi), lattice, options.smoothing_iterations);
  }
  const auto& dims = lattice.dims;

  // The water ends at the box's faces and at the cells the shells touch.
  const auto clip = [&](int i, int j, int k) {
    double& value = psi[node_index(dims, i, j, k)];
    if (value < tau) {
      mesh.clipped_nodes += value <= 0.0 ? 1 : 0;
      value = tau;
    }
  };
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
        if (i == 0 || j == 0 || k == 0 || i == dims[0] - 1 || j == dims[1] - 1 || k == dims[2] - 1)
          clip(i, j, k);
  const std::vector<Eigen::Vector3i> touched = cells_touched_by_shells(lattice, shells);
  for (const Eigen::Vector3i& c : touched)
    for (int corner = 0; corner < 8; ++corner)
      clip(c.x() + (corner & 1), c.y() + ((corner >> 1) & 1), c.z() + (corner >> 2));

  const auto grid = level_set_grid(psi, lattice);
  openvdb::tools::VolumeToMesh mesher(/*isovalue=*/0.0, options.adaptivity);
  if (options.adaptivity > 0.0 && !touched.empty()) {
    auto mask = std::make_shared<openvdb::BoolTree>(false);
    openvdb::tree::ValueAccessor<openvdb::BoolTree> accessor(*mask);
    for (const Eigen::Vector3i& c : touched)
      for (int dk = -kUnmergedRing; dk <= kUnmergedRing; ++dk)
        for (int dj = -kUnmergedRing; dj <= kUnmergedRing; ++dj)
          for (int di = -kUnmergedRing; di <= kUnmergedRing; ++di)
            accessor.setValueOn(openvdb::Coord(c.x() + di, c.y() + dj, c.z() + dk));
    mesher.setAdaptivityMask(mask);
  }
  mesher(*grid);

  const size_t points = mesher.pointListSize();
  mesh.positions.resize(static_cast<Eigen::Index>(points), 3);
  for (size_t p = 0; p < points; ++p)
    for (int a = 0; a < 3; ++a)
      mesh.positions(static_cast<Eigen::Index>(p), a) = mesher.pointList()[p][a];
  size_t triangles = 0;
  for (size_t n = 0; n < mesher.polygonPoolListSize(); ++n)
    triangles +=
        mesher.polygonPoolList()[n].numTriangles() + 2 * mesher.polygonPoolList()[n].numQuads();
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles), 3);
  Eigen::Index t = 0;
  // OpenVDB winds its polygons clockwise seen from outside (Houdini's convention); OBJ and
  // PLY readers expect counter-clockwise, hence the reversed order.
  const auto add = [&](unsigned a, unsigned b, unsigned c) {
    mesh.triangles.row(t++) << static_cast<int>(c), static_cast<int>(b), static_cast<int>(a);
  };
  for (size_t n = 0; n < mesher.polygonPoolListSize(); ++n) {
    const openvdb::tools::PolygonPool& pool = mesher.polygonPoolList()[n];
    for (size_t q = 0; q < pool.numQuads(); ++q) {
      const openvdb::Vec4I& quad = pool.quad(q);
      add(quad[0], quad[1], quad[2]);
      add(quad[0], quad[2], quad[3]);
    }
    for (size_t r = 0; r < pool.numTriangles(); ++r) {
      const openvdb::Vec3I& triangle = pool.triangle(r);
      add(triangle[0], triangle[1], triangle[2]);
    }
  }

  mesh.velocities = sdk::Positions::Zero(mesh.positions.rows(), 3);
  if (velocity != nullptr)
    for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
      const Eigen::Vector3d x = mesh.positions.row(v).transpose();
      for (int c = 0; c < 3; ++c) mesh.velocities(v, c) = trilinear(*velocity, c, x);
    }
  return mesh;
}

double mesh_volume(const sdk::Positions& positions, const sdk::Triangles& triangles) {
  double six_volume = 0.0;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::Vector3d a = positions.row(triangles(t, 0)).transpose();
    const Eigen::Vector3d b = positions.row(triangles(t, 1)).transpose();
    const Eigen::Vector3d c = positions.row(triangles(t, 2)).transpose();
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

double mesh_area(const sdk::Positions& positions, const sdk::Triangles& triangles) {
  double twice_area = 0.0;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::Vector3d a = positions.row(triangles(t, 0)).transpose();
    const Eigen::Vector3d b = positions.row(triangles(t, 1)).transpose();
    const Eigen::Vector3d c = positions.row(triangles(t, 2)).transpose();
    twice_area += (b - a).cross(c - a).norm();
  }
  return twice_area / 2.0;
}

}  // namespace shellflow::liquid_writer
