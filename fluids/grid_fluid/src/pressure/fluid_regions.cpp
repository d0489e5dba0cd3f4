#include "shellflow/grid_fluid/pressure/fluid_regions.hpp"

#include <omp.h>

#include <algorithm>
#include <utility>

#include "shellflow/grid/fingerprint.hpp"

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
  // A sealed cell's row is zero and its right-hand side the caller's to zero: no constant
  // to fix (a source's thousands of them cost two passes per CG iteration as groups).
  for (int r = 0; r < count(); ++r)
    if (enclosed[r] != 0 && (sealed.empty() || sealed[r] == 0)) group_of_region[r] = groups++;
  if (groups == 0) return {};
  std::vector<int> group(unknowns.empty() ? region.size() : unknowns.size());
  for (size_t u = 0; u < group.size(); ++u) {
    const int r = region[unknowns.empty() ? u : unknowns[u]];
    group[u] = r < 0 ? -1 : group_of_region[r];
  }
  return linear::ConstantNullSpace(std::move(group), groups);
}

namespace {

/// Union–find over the slabs' pieces of regions, each piece's root the piece with the
/// smallest first cell (so the regions keep the serial fill's numbering).
int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

/// The flood fill, in parallel: each thread fills the pieces of regions within its slab of
/// z-planes, noting the faces to the slab above that join two pieces; the pieces are then
/// joined, and the regions numbered by their first cell in cell order, as a serial fill
/// from cell 0 numbers them (the numbering does not depend on the thread count).
void fill_regions(const grid::UniformGrid& grid,
                  const std::array<std::vector<std::uint8_t>, 3>& closed,
                  const bool (&open_side)[3][2], std::span<const std::uint8_t> liquid,
                  FluidRegions& out, std::vector<std::int64_t>& counts) {
  const std::int64_t cells = grid.size(Location::Cell);
  const bool water = !liquid.empty();
  constexpr int kAir = -2, kUnvisited = -1;
  std::fill(out.region.begin(), out.region.end(), kUnvisited);
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
  const int slabs = std::max(1, std::min(omp_get_max_threads(), n.z()));
  const auto first_plane = [&](int s) { return static_cast<int>(std::int64_t(n.z()) * s / slabs); };
  struct Piece {
    std::int64_t first_cell;
    std::int64_t size;
    bool open, any_face;
  };
  std::vector<std::vector<Piece>> pieces(slabs);
  // Per slab: pairs (cell of its top plane, cell above it) across a non-closed z face.
  std::vector<std::vector<std::pair<std::int64_t, std::int64_t>>> links(slabs);
#pragma omp parallel for schedule(static, 1)
  for (int s = 0; s < slabs; ++s) {
    const int k_lo = first_plane(s), k_hi = first_plane(s + 1);  // planes [k_lo, k_hi)
    auto& mine = pieces[s];
    std::vector<std::int64_t> stack;
    for (std::int64_t seed = k_lo * plane; seed < k_hi * plane; ++seed) {
      if (out.region[seed] != kUnvisited) continue;
      const int r = static_cast<int>(mine.size());  // local id within the slab
      Piece piece{seed, 0, false, false};
      out.region[seed] = r;
      stack.push_back(seed);
      // Visits the neighbour across a non-closed face, or notes an open domain face.
      const auto visit = [&](bool inside, std::int64_t nb, bool open_domain_face) {
        piece.any_face = true;
        if (!inside) {
          piece.open = piece.open || open_domain_face;
        } else if (out.region[nb] == kAir) {
          piece.open = true;  // a face to an air cell: Dirichlet p = 0 (§4.3)
        } else if (out.region[nb] == kUnvisited) {
          out.region[nb] = r;
          stack.push_back(nb);
        }
      };
      while (!stack.empty()) {
        const std::int64_t c = stack.back();
        stack.pop_back();
        ++piece.size;
        // Face indices from the cell's row (UniformGrid layout), without a division per face.
        const std::int64_t i = c % nx, j = (c / nx) % ny, k = c / plane;
        const std::int64_t fx = i + (nx + 1) * (j + ny * k);
        const std::int64_t fy = i + nx * (j + (ny + 1) * k);
        if (!closed_x[fx]) visit(i > 0, c - 1, open_side[0][0]);
        if (!closed_x[fx + 1]) visit(i + 1 < nx, c + 1, open_side[0][1]);
        if (!closed_y[fy]) visit(j > 0, c - nx, open_side[1][0]);
        if (!closed_y[fy + nx]) visit(j + 1 < ny, c + nx, open_side[1][1]);
        // Across the slab's own bottom and top planes the neighbour is another slab's:
        // an air cell there opens the piece; a fluid cell is joined below.
        // (`liquid`, not the other slab's labels, which its thread is writing).
        if (!closed_z[c]) {
          if (k == 0 || k > k_lo) {
            visit(k > 0, c - plane, open_side[2][0]);
          } else {
            piece.any_face = true;
            piece.open = piece.open || (water && liquid[c - plane] == 0);
          }
        }
        if (!closed_z[c + plane]) {
          if (k + 1 == n.z() || k + 1 < k_hi) {
            visit(k + 1 < n.z(), c + plane, open_side[2][1]);
          } else {
            piece.any_face = true;
            if (water && liquid[c + plane] == 0)
              piece.open = true;
            else
              links[s].emplace_back(c, c + plane);
          }
        }
      }
      mine.push_back(piece);
    }
  }
  // The pieces, numbered slab after slab (so in the order of their first cells).
  std::vector<int> offset(slabs + 1, 0);
  for (int s = 0; s < slabs; ++s) offset[s + 1] = offset[s] + static_cast<int>(pieces[s].size());
  std::vector<int> parent(offset[slabs]);
  for (int p = 0; p < offset[slabs]; ++p) parent[p] = p;
  for (int s = 0; s + 1 < slabs; ++s)
    for (const auto& [below, above] : links[s]) {
      const int a = find_root(parent, offset[s] + out.region[below]);
      const int b = find_root(parent, offset[s + 1] + out.region[above]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root: the smaller first cell
    }
  // A region per root, in the order of the roots (their first cells): the serial numbering.
  std::vector<int> region_of_piece(offset[slabs]);
  out.enclosed.clear();
  out.sealed.clear();
  std::vector<std::uint8_t> open, any_face;
  for (int s = 0; s < slabs; ++s)
    for (int p = 0; p < static_cast<int>(pieces[s].size()); ++p) {
      const int id = offset[s] + p, root = find_root(parent, id);
      const Piece& piece = pieces[s][p];
      if (root == id) {
        region_of_piece[id] = static_cast<int>(counts.size());
        counts.push_back(0);
        open.push_back(0);
        any_face.push_back(0);
      } else {
        region_of_piece[id] = region_of_piece[root];  // root < id: numbered already
      }
      const int r = region_of_piece[id];
      counts[r] += piece.size;
      open[r] |= piece.open ? 1 : 0;
      any_face[r] |= piece.any_face ? 1 : 0;
    }
  for (size_t r = 0; r < counts.size(); ++r) {
    out.enclosed.push_back(open[r] ? 0 : 1);
    out.sealed.push_back(any_face[r] ? 0 : 1);
  }
#pragma omp parallel for schedule(static, 1)
  for (int s = 0; s < slabs; ++s)
    for (std::int64_t c = first_plane(s) * plane; c < first_plane(s + 1) * plane; ++c) {
      const int local = out.region[c];
      out.region[c] = local >= 0 ? region_of_piece[offset[s] + local] : -1;
    }
}

}  // namespace

void label_fluid_regions(const grid::UniformGrid& grid,
                         const std::array<std::vector<std::uint8_t>, 3>& closed,
                         const DomainBoundary& boundary, FluidRegions& out, bool interior_closed,
                         std::span<const std::uint8_t> liquid) {
  const std::int64_t cells = grid.size(Location::Cell);
  out.keyed = false;
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
    fill_regions(grid, closed, open_side, liquid, out, counts);
  }
  // Cells of each region, in cell order (CSR).
  const int regions = out.count();
  out.start.assign(regions + 1, 0);
  for (int r = 0; r < regions; ++r) out.start[r + 1] = out.start[r] + counts[r];
  out.cells.resize(out.start[regions]);
  if (regions == 1 && out.start[1] == cells) {
#pragma omp parallel for schedule(static)
    for (std::int64_t cell = 0; cell < cells; ++cell)
      out.cells[cell] = static_cast<std::int32_t>(cell);
    return;
  }
  // In parallel over slabs of cells: each slab's share of a region follows the slabs before.
  const int slabs = omp_get_max_threads();
  const auto first_cell = [&](int s) { return cells * s / slabs; };
  std::vector<std::vector<std::int64_t>> fill(slabs, std::vector<std::int64_t>(regions, 0));
#pragma omp parallel for schedule(static, 1)
  for (int s = 0; s < slabs; ++s)
    for (std::int64_t cell = first_cell(s); cell < first_cell(s + 1); ++cell)
      if (out.region[cell] >= 0) ++fill[s][out.region[cell]];
  for (int r = 0; r < regions; ++r) {
    std::int64_t next = out.start[r];
    for (int s = 0; s < slabs; ++s) next += std::exchange(fill[s][r], next);
  }
#pragma omp parallel for schedule(static, 1)
  for (int s = 0; s < slabs; ++s)
    for (std::int64_t cell = first_cell(s); cell < first_cell(s + 1); ++cell)
      if (out.region[cell] >= 0)
        out.cells[fill[s][out.region[cell]]++] = static_cast<std::int32_t>(cell);
}

bool update_fluid_regions(const grid::UniformGrid& grid,
                          const std::array<std::vector<std::uint8_t>, 3>& closed,
                          const DomainBoundary& boundary, FluidRegions& out, bool interior_closed,
                          std::span<const std::uint8_t> liquid) {
  std::uint64_t key = interior_closed ? 1 : 0;  // then one bit per open side
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side)
      key = 2 * key + (boundary.side(a, side).type == BoundaryType::Open ? 1 : 0);
  if (liquid.empty()) {
    for (int a = 0; a < 3; ++a)
      key = grid::fingerprint_of(std::span<const std::uint8_t>(closed[a]), key);
    if (out.keyed && out.key == key) return false;
  }
  label_fluid_regions(grid, closed, boundary, out, interior_closed, liquid);
  out.keyed = liquid.empty();  // the liquid changes every step: never kept
  out.key = key;
  return true;
}

}  // namespace shellflow::grid_fluid
