#pragma once
// UniformGrid: the index space of a uniform Cartesian grid (no storage). Every grid
// field (node, cell or face values of the MAC grid, §4) is a flat contiguous array
// reached through `index()`, whose layout is documented once here.
//
// Geometry: cells are cubes of side dx; cell (i, j, k) spans
//   [origin + (i, j, k) * dx, origin + (i + 1, j + 1, k + 1) * dx].
// Sample positions per location (Location):
//   Node  (i, j, k): origin + (i, j, k) dx                 counts (nx+1, ny+1, nz+1)
//   Cell  (i, j, k): origin + (i+1/2, j+1/2, k+1/2) dx     counts (nx,   ny,   nz)
//   FaceX (i, j, k): origin + (i, j+1/2, k+1/2) dx         counts (nx+1, ny,   nz)
//   FaceY (i, j, k): origin + (i+1/2, j, k+1/2) dx         counts (nx,   ny+1, nz)
//   FaceZ (i, j, k): origin + (i+1/2, j+1/2, k) dx         counts (nx,   ny,   nz+1)
// Flat layout (x fastest): index = i + ni * (j + nj * k), with (ni, nj, nk) = counts(location).

#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace shellflow::grid {

/// Where on the grid a value lives.
enum class Location : int { Node = 0, Cell = 1, FaceX = 2, FaceY = 3, FaceZ = 4 };
inline constexpr int kLocationCount = 5;
inline constexpr std::array<Location, kLocationCount> kAllLocations = {
    Location::Node, Location::Cell, Location::FaceX, Location::FaceY, Location::FaceZ};

/// An inclusive range of grid indices [lo, hi] per axis; empty when any hi < lo.
struct IndexBox {
  Eigen::Vector3i lo;
  Eigen::Vector3i hi;
  bool empty() const { return (hi.array() < lo.array()).any(); }
  bool contains(const Eigen::Vector3i& ijk) const {
    return (ijk.array() >= lo.array()).all() && (ijk.array() <= hi.array()).all();
  }
};

class UniformGrid {
 public:
  UniformGrid() = default;
  /// `cells`: cell counts per axis (each >= 1); `dx` > 0; `origin`: the corner of cell (0,0,0).
  UniformGrid(const Eigen::Vector3d& origin, double dx, const Eigen::Vector3i& cells);

  const Eigen::Vector3d& origin() const { return m_origin; }
  double dx() const { return m_dx; }
  const Eigen::Vector3i& cells() const { return m_cells; }
  /// The far corner of the domain.
  Eigen::Vector3d upper() const { return m_origin + m_dx * m_cells.cast<double>(); }

  /// Sample counts per axis at `location` (see the table above).
  Eigen::Vector3i counts(Location location) const {
    Eigen::Vector3i n = m_cells;
    if (location == Location::Node) n.array() += 1;
    if (location == Location::FaceX) n.x() += 1;
    if (location == Location::FaceY) n.y() += 1;
    if (location == Location::FaceZ) n.z() += 1;
    return n;
  }
  /// Total number of samples at `location`.
  std::int64_t size(Location location) const {
    const Eigen::Vector3i n = counts(location);
    return std::int64_t{n.x()} * n.y() * n.z();
  }

  /// THE flat index helper: index = i + ni * (j + nj * k), x fastest.
  std::int64_t index(Location location, int i, int j, int k) const {
    const Eigen::Vector3i n = counts(location);
    return i + std::int64_t{n.x()} * (j + std::int64_t{n.y()} * k);
  }
  std::int64_t index(Location location, const Eigen::Vector3i& ijk) const {
    return index(location, ijk.x(), ijk.y(), ijk.z());
  }
  /// Inverse of index().
  Eigen::Vector3i coordinates(Location location, std::int64_t flat) const {
    const Eigen::Vector3i n = counts(location);
    const std::int64_t plane = std::int64_t{n.x()} * n.y();
    const int k = static_cast<int>(flat / plane);
    const std::int64_t rest = flat - plane * k;
    const int j = static_cast<int>(rest / n.x());
    const int i = static_cast<int>(rest - std::int64_t{n.x()} * j);
    return {i, j, k};
  }
  bool contains(Location location, const Eigen::Vector3i& ijk) const {
    const Eigen::Vector3i n = counts(location);
    return (ijk.array() >= 0).all() && (ijk.array() < n.array()).all();
  }

  /// Offset of sample (0,0,0) of `location` from the origin, in units of dx.
  static Eigen::Vector3d stagger(Location location);
  /// World position of sample (i, j, k) at `location`.
  Eigen::Vector3d position(Location location, const Eigen::Vector3i& ijk) const {
    return m_origin + m_dx * (ijk.cast<double>() + stagger(location));
  }
  Eigen::Vector3d position(Location location, std::int64_t flat) const {
    return position(location, coordinates(location, flat));
  }

  /// The samples of `location` whose positions lie in the closed box [lower, upper],
  /// clamped to the grid (possibly empty). Cost O(1).
  IndexBox samples_in_box(Location location, const Eigen::Vector3d& lower,
                          const Eigen::Vector3d& upper) const;

 private:
  Eigen::Vector3d m_origin = Eigen::Vector3d::Zero();
  double m_dx = 1.0;
  Eigen::Vector3i m_cells = Eigen::Vector3i::Ones();
};

}  // namespace shellflow::grid
