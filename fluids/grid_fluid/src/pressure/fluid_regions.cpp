#include "shellflow/grid_fluid/pressure/fluid_regions.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

int FluidRegions::enclosed_count() const {
  int n = 0;
  for (const auto e : enclosed) n += e;
  return n;
}

linear::ConstantNullSpace FluidRegions::null_space(std::span<const std::int64_t> unknowns) const {
  std::vector<int> group_of_region(count(), -1);
  int groups = 0;
  for (int r = 0; r < count(); ++r)
    if (enclosed[r] != 0) group_of_region[r] = groups++;
  if (groups == 0) return {};
  std::vector<int> group(unknowns.empty() ? region.size() : unknowns.size());
  for (size_t u = 0; u < group.size(); ++u) {
    const int r = region[unknowns.empty() ? u : unknowns[u]];
    group[u] = r < 0 ? -1 : group_of_region[r];
  }
  return linear::ConstantNullSpace(std::move(group), groups);
}

void label_fluid_regions(const grid::UniformGrid& grid,
                         const std::array<std::vector<std::uint8_t>, 3>& closed,
                         const DomainBoundary& boundary, FluidRegions& out, bool interior_closed,
                         std::span<const std::uint8_t> liquid) {
  const std::int64_t cells = grid.size(Location::Cell);
  out.region.resize(cells);
  out.enclosed.clear();
  out.sealed.clear();
  std::vector<std::int64_t> counts;
  const bool open_side[3][2] = {{boundary.side(0, 0).type == BoundaryType::Open,
                                 boundary.side(0, 1).type == BoundaryType::Open},
                                {boundary.side(1, 0).type == BoundaryType::Open,
                                 boundary.side(1, 1).type == BoundaryType::Open},
                                {boundary.side(2, 0).type == BoundaryType::Open,
                                 boundary.side(2, 1).type == BoundaryType::Open}};
  const bool water = !liquid.empty();
  if (!interior_closed && !water) {
    // Only domain faces may be closed: every cell reaches every other (the fast path
    // away from shells); the region is open when one side of the domain is.
    bool open = false;
    for (int a = 0; a < 3; ++a) open = open || open_side[a][0] || open_side[a][1];
    std::fill(out.region.begin(), out.region.end(), 0);
    out.enclosed.push_back(open ? 0 : 1);
    out.sealed.push_back(0);
    counts.push_back(cells);
  } else {
    std::fill(out.region.begin(), out.region.end(), -1);
    // Air cells are never visited: marked so, with `kAir` until the end.
    constexpr int kAir = -2;
    if (water) {
#pragma omp parallel for schedule(static)
      for (std::int64_t c = 0; c < cells; ++c)
        if (liquid[c] == 0) out.region[c] = kAir;
    }
    const Eigen::Vector3i n = grid.cells();
    const std::int64_t nx = n.x(), ny = n.y(), plane = nx * ny;
    const std::uint8_t* closed_x = closed[0].data();
    const std::uint8_t* closed_y = closed[1].data();
    const std::uint8_t* closed_z = closed[2].data();
    std::vector<std::int64_t> stack;
    for (std::int64_t seed = 0; seed < cells; ++seed) {
      if (out.region[seed] != -1) continue;
      const int r = out.count();
      bool open = false;
      bool any_face = false;  // a non-closed face: the cell has a pressure unknown
      std::int64_t size = 0;
      out.region[seed] = r;
      stack.push_back(seed);
      // Visits the neighbour across a non-closed face, or notes an open domain face.
      const auto visit = [&](bool inside, std::int64_t nb, bool open_domain_face) {
        any_face = true;
        if (!inside) {
          open = open || open_domain_face;
        } else if (out.region[nb] == kAir) {
          open = true;  // a face to an air cell: Dirichlet p = 0 (§4.3)
        } else if (out.region[nb] < 0) {
          out.region[nb] = r;
          stack.push_back(nb);
        }
      };
      while (!stack.empty()) {
        const std::int64_t c = stack.back();
        stack.pop_back();
        ++size;
        // Face indices from the cell's row (UniformGrid layout), without a division per face.
        const std::int64_t i = c % nx, j = (c / nx) % ny, k = c / plane;
        const std::int64_t fx = i + (nx + 1) * (j + ny * k);
        const std::int64_t fy = i + nx * (j + (ny + 1) * k);
        if (!closed_x[fx]) visit(i > 0, c - 1, open_side[0][0]);
        if (!closed_x[fx + 1]) visit(i + 1 < nx, c + 1, open_side[0][1]);
        if (!closed_y[fy]) visit(j > 0, c - nx, open_side[1][0]);
        if (!closed_y[fy + nx]) visit(j + 1 < ny, c + nx, open_side[1][1]);
        if (!closed_z[c]) visit(k > 0, c - plane, open_side[2][0]);
        if (!closed_z[c + plane]) visit(k + 1 < n.z(), c + plane, open_side[2][1]);
      }
      out.enclosed.push_back(open ? 0 : 1);
      out.sealed.push_back(any_face ? 0 : 1);
      counts.push_back(size);
    }
    if (water) {
#pragma omp parallel for schedule(static)
      for (std::int64_t c = 0; c < cells; ++c)
        if (out.region[c] == kAir) out.region[c] = -1;
    }
  }
  // Cells of each region, in cell order (CSR).
  const int regions = out.count();
  out.start.assign(regions + 1, 0);
  for (int r = 0; r < regions; ++r) out.start[r + 1] = out.start[r] + counts[r];
  out.cells.resize(out.start[regions]);
  if (regions == 1 && out.start[1] == cells) {
#pragma omp parallel for schedule(static)
    for (std::int64_t cell = 0; cell < cells; ++cell) out.cells[cell] = cell;
    return;
  }
  std::vector<std::int64_t> fill(out.start.begin(), out.start.end() - 1);
  for (std::int64_t cell = 0; cell < cells; ++cell)
    if (out.region[cell] >= 0) out.cells[fill[out.region[cell]]++] = cell;
}

}  // namespace shellflow::grid_fluid
