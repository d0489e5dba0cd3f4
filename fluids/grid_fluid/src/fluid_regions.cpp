#include "shellflow/grid_fluid/fluid_regions.hpp"

#include "shellflow/grid_fluid/mac_grid.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

void label_fluid_regions(const grid::UniformGrid& grid,
                         const std::array<std::vector<std::uint8_t>, 3>& closed,
                         const DomainBoundary& boundary, FluidRegions& out) {
  const std::int64_t cells = grid.size(Location::Cell);
  const Eigen::Vector3i n = grid.cells();
  out.region.assign(cells, -1);
  out.enclosed.clear();
  std::vector<std::int64_t> counts;
  std::vector<std::int64_t> stack;
  for (std::int64_t seed = 0; seed < cells; ++seed) {
    if (out.region[seed] >= 0) continue;
    const int r = static_cast<int>(out.enclosed.size());
    bool open = false;
    std::int64_t size = 0;
    out.region[seed] = r;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::int64_t cell = stack.back();
      stack.pop_back();
      ++size;
      const Eigen::Vector3i c = grid.coordinates(Location::Cell, cell);
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          Eigen::Vector3i f = c;
          f[a] += side;
          if (closed[a][grid.index(face_location(a), f)] != 0) continue;
          Eigen::Vector3i nb = c;
          nb[a] += side == 0 ? -1 : 1;
          if (nb[a] < 0 || nb[a] >= n[a]) {
            open = open || boundary.side(a, side).type == BoundaryType::Open;
            continue;
          }
          const std::int64_t next = grid.index(Location::Cell, nb);
          if (out.region[next] >= 0) continue;
          out.region[next] = r;
          stack.push_back(next);
        }
    }
    out.enclosed.push_back(open ? 0 : 1);
    counts.push_back(size);
  }
  const int regions = out.count();
  out.start.assign(regions + 1, 0);
  for (int r = 0; r < regions; ++r) out.start[r + 1] = out.start[r] + counts[r];
  out.cells.resize(cells);
  std::vector<std::int64_t> fill(out.start.begin(), out.start.end() - 1);
  for (std::int64_t cell = 0; cell < cells; ++cell) out.cells[fill[out.region[cell]]++] = cell;
}

}  // namespace shellflow::grid_fluid
