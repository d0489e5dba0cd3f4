#include "shellflow/grid_fluid/water/volume_budget.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/ordered_sum.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {
/// The fraction of a triangle where the linear interpolant of its corner values is below
/// zero, exact: a corner triangle (one corner wet) or its complement (two).
double triangle_water_fraction(double a, double b, double c) {
  // φ <= 0 is water, as in LevelSet::volume.
  const int wet = (a <= 0.0) + (b <= 0.0) + (c <= 0.0);
  if (wet == 0) return 0.0;
  if (wet == 3) return 1.0;
  // The corner on its own (wet alone, or dry alone) to a.
  if ((b <= 0.0) == (wet == 1)) std::swap(a, b);
  if ((c <= 0.0) == (wet == 1)) std::swap(a, c);
  const double corner = (a / (a - b)) * (a / (a - c));
  return wet == 1 ? corner : 1.0 - corner;
}

/// Adds to `wet` the integral over f in [0, end] (end <= 1) of the wet fraction of the face's
/// section (1 − f) near + f far (corner φ in face_water_fraction's order). Its φ is linear
/// in f, its wet fraction smooth between where its corners change sign, so three Gauss
/// points on each such piece integrate it to round-off (a flat surface's step exactly).
void add_layer_wet(const std::array<double, 4>& near, const std::array<double, 4>& far, double end,
                   double& wet) {
  std::array<double, 6> cuts{0.0};
  int count = 1;
  for (int m = 0; m < 4; ++m)
    if ((near[m] <= 0.0) != (far[m] <= 0.0)) {
      const double at = near[m] / (near[m] - far[m]);
      if (at > 0.0 && at < end) cuts[count++] = at;
    }
  cuts[count++] = end;
  for (int x = 1; x < count; ++x)  // insertion sort: at most six
    for (int y = x; y > 0 && cuts[y] < cuts[y - 1]; --y) std::swap(cuts[y], cuts[y - 1]);
  const auto fraction = [&](double f) {
    std::array<double, 4> section;
    for (int m = 0; m < 4; ++m) section[m] = (1.0 - f) * near[m] + f * far[m];
    return face_water_fraction(section);
  };
  constexpr double kGauss = 0.7745966692414834;  // sqrt(3/5)
  for (int piece = 0; piece + 1 < count; ++piece) {
    const double mid = 0.5 * (cuts[piece] + cuts[piece + 1]);
    const double half = 0.5 * (cuts[piece + 1] - cuts[piece]);
    if (half <= 0.0) continue;
    wet += half * (5.0 / 9.0 * fraction(mid - kGauss * half) + 8.0 / 9.0 * fraction(mid) +
                   5.0 / 9.0 * fraction(mid + kGauss * half));
  }
}

/// The water [m^3] that the face velocity u_f on an open side's face (family `axis`, at
/// coordinates `ijk`; `max_side`: on the box's max face) carries out of the domain over dt,
/// from the cell-centred φ: nothing where u_f points in, else the face's wet fraction
/// integrated over the depth u_f dt upstream (swept so, not as a rate: a surface passes a
/// face within a step, and a rate at either end of the step counts it half). The section's
/// corners (MAC nodes) take the mean of the four rows of centres about them (clamped at
/// the sides); along the normal φ is linear between planes of centres.
double swept_out_of_cells(const LevelSet& level_set, const MacGrid& mac, int axis,
                          const Eigen::Vector3i& ijk, bool max_side, double dt) {
  const grid::UniformGrid& grid = mac.grid();
  const double u = mac.face_velocity(axis)[grid.index(face_location(axis), ijk)];
  const double outward = max_side ? u : -u;
  if (!(outward > 0.0)) return 0.0;
  const Eigen::Vector3i n = grid.cells();
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  const grid::UniformGrid& lattice = level_set.grid();
  const auto& phi = level_set.phi();
  const auto section = [&](int plane) {
    std::array<double, 4> corner;
    for (int m = 0; m < 4; ++m) {
      double sum = 0.0;
      for (int q = 0; q < 4; ++q) {
        Eigen::Vector3i cell;
        cell[axis] = plane;
        cell[b] = std::clamp(ijk[b] + (m & 1) - 1 + (q & 1), 0, n[b] - 1);
        cell[c] = std::clamp(ijk[c] + (m >> 1) - 1 + (q >> 1), 0, n[c] - 1);
        sum += phi[lattice.index(Location::Node, cell)];
      }
      corner[m] = 0.25 * sum;
    }
    return corner;
  };
  const double dx = grid.dx(), depth = outward * dt;
  const int first = max_side ? n[axis] - 1 : 0, step = max_side ? -1 : 1;  // upstream
  const auto plane = [&](int layer) { return std::clamp(first + step * layer, 0, n[axis] - 1); };
  std::array<double, 4> near = section(first), far = section(plane(1));
  // From the face to the first centres: the linear interpolant of the first two planes
  // continued (the level set's own surface, which the advection carries out), not the
  // constant ghost, which counts a surface there as at the first centres.
  std::array<double, 4> at_face;
  for (int m = 0; m < 4; ++m) at_face[m] = 1.5 * near[m] - 0.5 * far[m];
  double strip = 0.0;  // in half cells
  add_layer_wet(at_face, near, std::min(1.0, 2.0 * depth / dx), strip);
  double wet = 0.5 * strip;  // in cells
  for (int layer = 0; (layer + 0.5) * dx < depth; ++layer) {
    if (layer > 0) far = section(plane(layer + 1));
    add_layer_wet(near, far, std::min(1.0, depth / dx - layer - 0.5), wet);
    near = far;
  }
  return wet * dx * dx * dx;
}

}  // namespace

double face_water_fraction(const std::array<double, 4>& corner) {
  return 0.5 * (triangle_water_fraction(corner[0], corner[1], corner[3]) +
                triangle_water_fraction(corner[0], corner[2], corner[3]));
}

grid::IndexBox emitter_reach(const LevelSet& level_set, const WaterSource& source) {
  const grid::UniformGrid& grid = level_set.grid();
  const grid::IndexBox samples = source.bounding_nodes(grid, level_set.band());
  if (samples.empty()) return samples;
  const Eigen::Vector3i last = level_set.mac_grid().cells() - Eigen::Vector3i::Ones();
  // A cell centre's φ is interpolated over the lattice cells to each side of it, which
  // reach half into the next MAC cell.
  return {(samples.lo.array() - 1).max(0).matrix(),
          (samples.hi.array() + 1).min(last.array()).matrix()};
}

namespace {
/// Is cell c (any coordinates) one of the emitter's: in the grid, its centre inside?
bool emitter_cell(const grid::UniformGrid& grid, const WaterSource& source,
                  const Eigen::Vector3i& c) {
  if ((c.array() < 0).any() || (c.array() >= grid.cells().array()).any()) return false;
  return source.contains(grid.position(Location::Cell, c));
}
}  // namespace

bool emitter_has_water(const LevelSet& level_set, const WaterSource& source) {
  const grid::UniformGrid& grid = level_set.mac_grid();
  const grid::IndexBox box = source.bounding_cells(grid);
  for (int k = box.lo.z(); k <= box.hi.z(); ++k)
    for (int j = box.lo.y(); j <= box.hi.y(); ++j)
      for (int i = box.lo.x(); i <= box.hi.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        if (!emitter_cell(grid, source, c)) continue;
        if (level_set.phi()[grid.index(Location::Cell, c)] < 0.0) return true;
      }
  return false;
}

double emitter_held_flow(const grid::UniformGrid& grid, const WaterSource& source, double t) {
  const Eigen::Vector3i n = grid.cells();
  double flow = 0.0;
  for (int a = 0; a < 3; ++a) {
    std::vector<SourceFace> faces;
    source.append_faces(t, grid, a, faces);
    const Location loc = face_location(a);
    for (const SourceFace& f : faces) {
      const Eigen::Vector3i face = grid.coordinates(loc, f.face);
      if (face[a] == 0 || face[a] == n[a]) continue;  // on the domain's side: no cell beyond
      Eigen::Vector3i minus = face;
      minus[a] -= 1;
      const bool in_minus = emitter_cell(grid, source, minus);
      if (in_minus == emitter_cell(grid, source, face)) continue;  // not on its surface
      flow += std::max(0.0, (in_minus ? 1.0 : -1.0) * f.velocity[a]);
    }
  }
  return flow * grid.dx() * grid.dx();
}

double open_side_outflow(const LevelSet& level_set, const MacGrid& mac,
                         const std::array<bool, 6>& open, double dt) {
  const Eigen::Vector3i n = mac.grid().cells();
  double volume = 0.0;
  for (int side = 0; side < 6; ++side) {
    if (!open[side]) continue;
    const int a = side / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const bool max_side = side % 2 == 1;
    // One term per row of faces along b, each summed in order: the same bits on any
    // number of threads.
    volume += ordered_sum(n[c], [&](std::int64_t k) {
      double row = 0.0;
      Eigen::Vector3i face;
      face[a] = max_side ? n[a] : 0;
      face[c] = static_cast<int>(k);
      for (face[b] = 0; face[b] < n[b]; ++face[b])
        row += swept_out_of_cells(level_set, mac, a, face, max_side, dt);
      return row;
    });
  }
  return volume;
}

}  // namespace shellflow::grid_fluid
