// The parallel region labelling (label_fluid_regions) against a plain union–find over the
// same faces: on random closed faces and random air, every thread count gives the regions,
// their numbering (by first cell), their open/enclosed and sealed flags and their cell lists
// of the serial definition, exactly.

#include <gtest/gtest.h>
#include <omp.h>

#include <numeric>
#include <random>

#include "shellflow/grid_fluid/pressure/fluid_regions.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

struct Case {
  grid::UniformGrid grid;
  std::array<std::vector<std::uint8_t>, 3> closed;
  std::vector<std::uint8_t> liquid;  // empty: every cell fluid
  DomainBoundary boundary;
};

Case random_case(const Eigen::Vector3i& cells, double closed_share, double air_share,
                 std::uint64_t seed) {
  Case c{grid::UniformGrid(Eigen::Vector3d::Zero(), 1.0, cells), {}, {}, DomainBoundary()};
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution closes(closed_share), airy(air_share);
  for (int a = 0; a < 3; ++a) {
    c.closed[a].resize(c.grid.size(a == 0   ? Location::FaceX
                                   : a == 1 ? Location::FaceY
                                            : Location::FaceZ));
    for (auto& f : c.closed[a]) f = closes(rng) ? 1 : 0;
  }
  if (air_share > 0.0) {
    c.liquid.resize(c.grid.size(Location::Cell));
    for (auto& l : c.liquid) l = airy(rng) ? 0 : 1;
  }
  c.boundary.side(1, 1).type = BoundaryType::Open;  // the top lets fluid out
  return c;
}

/// The definition: cells joined through non-closed faces (air cells take no part), a region
/// numbered by its first cell, open through a non-closed face on an open side or to air,
/// sealed when it is one cell without a non-closed face.
FluidRegions reference(const Case& c) {
  const Eigen::Vector3i n = c.grid.cells();
  const std::int64_t cells = c.grid.size(Location::Cell);
  const auto fluid = [&](std::int64_t cell) { return c.liquid.empty() || c.liquid[cell] != 0; };
  std::vector<std::int64_t> parent(cells);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](std::int64_t x) {
    while (parent[x] != x) x = parent[x];
    return x;
  };
  std::vector<std::uint8_t> open(cells, 0), any_face(cells, 0);
  for (int a = 0; a < 3; ++a) {
    const Location loc = a == 0 ? Location::FaceX : a == 1 ? Location::FaceY : Location::FaceZ;
    for (std::int64_t f = 0; f < c.grid.size(loc); ++f) {
      if (c.closed[a][f] != 0) continue;
      const Eigen::Vector3i ijk = c.grid.coordinates(loc, f);
      Eigen::Vector3i below = ijk;
      below[a] -= 1;
      const bool has_below = ijk[a] > 0, has_above = ijk[a] < n[a];
      const std::int64_t lo = has_below ? c.grid.index(Location::Cell, below) : -1;
      const std::int64_t hi = has_above ? c.grid.index(Location::Cell, ijk) : -1;
      for (const auto& [me, other, max_side] :
           {std::tuple{lo, hi, 1}, std::tuple{hi, lo, 0}}) {
        if (me < 0 || !fluid(me)) continue;
        any_face[me] = 1;
        if (other < 0)
          open[me] |= c.boundary.side(a, max_side).type == BoundaryType::Open ? 1 : 0;
        else if (!fluid(other))
          open[me] = 1;
      }
      if (lo >= 0 && hi >= 0 && fluid(lo) && fluid(hi)) {
        const std::int64_t x = find(lo), y = find(hi);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
    }
  }
  FluidRegions out;
  out.region.assign(cells, -1);
  std::vector<int> id(cells, -1);
  std::vector<std::vector<std::int64_t>> members;
  for (std::int64_t cell = 0; cell < cells; ++cell) {
    if (!fluid(cell)) continue;
    const std::int64_t root = find(cell);
    if (id[root] < 0) {
      id[root] = static_cast<int>(members.size());
      members.emplace_back();
      out.enclosed.push_back(1);
      out.sealed.push_back(1);
    }
    const int r = id[root];
    out.region[cell] = r;
    members[r].push_back(cell);
    if (open[cell]) out.enclosed[r] = 0;
    if (any_face[cell]) out.sealed[r] = 0;
  }
  out.start.push_back(0);
  for (const auto& m : members) {
    out.cells.insert(out.cells.end(), m.begin(), m.end());
    out.start.push_back(static_cast<std::int64_t>(out.cells.size()));
  }
  return out;
}

TEST(FluidRegions, ParallelFillMatchesTheDefinitionForEveryThreadCount) {
  const int threads_before = omp_get_max_threads();
  int cases = 0, most_regions = 0;
  for (const Eigen::Vector3i& cells : {Eigen::Vector3i(9, 7, 13), Eigen::Vector3i(5, 4, 1),
                                      Eigen::Vector3i(6, 3, 2), Eigen::Vector3i(12, 12, 12)})
    for (const double closed_share : {0.2, 0.45, 0.7})  // one region .. many (percolation ~0.75)
      for (const double air_share : {0.0, 0.3}) {
        const Case c = random_case(cells, closed_share, air_share, 17u + cases);
        const FluidRegions want = reference(c);
        most_regions = std::max(most_regions, want.count());
        for (const int threads : {1, 2, 3, 7}) {
          omp_set_num_threads(threads);
          FluidRegions got;
          label_fluid_regions(c.grid, c.closed, c.boundary, got, true,
                              c.liquid.empty() ? std::span<const std::uint8_t>()
                                               : std::span<const std::uint8_t>(c.liquid));
          const std::string where = "cells " + std::to_string(cells.x()) + "x" +
                                    std::to_string(cells.y()) + "x" + std::to_string(cells.z()) +
                                    ", closed " + std::to_string(closed_share) + ", air " +
                                    std::to_string(air_share) + ", " + std::to_string(threads) +
                                    " threads";
          EXPECT_EQ(got.region, want.region) << where;
          EXPECT_EQ(got.enclosed, want.enclosed) << where;
          EXPECT_EQ(got.sealed, want.sealed) << where;
          EXPECT_EQ(got.start, want.start) << where;
          EXPECT_EQ(got.cells, want.cells) << where;
        }
        ++cases;
      }
  omp_set_num_threads(threads_before);
  // The cases span one region to many, so that joins across slabs are exercised.
  EXPECT_GT(most_regions, 50);
}

// update_fluid_regions keeps the labelling only while its inputs are the same: the same
// closed faces, open sides and interior flag, and no water. Any change relabels, and the
// result always equals the definition.
TEST(FluidRegions, KeptOnlyWhileTheClosedFacesAndSidesAreTheSame) {
  Case c = random_case({9, 7, 8}, 0.35, 0.0, 5);
  FluidRegions got;
  EXPECT_TRUE(update_fluid_regions(c.grid, c.closed, c.boundary, got));
  EXPECT_FALSE(update_fluid_regions(c.grid, c.closed, c.boundary, got));  // same inputs
  EXPECT_EQ(got.region, reference(c).region);

  c.closed[1][c.closed[1].size() / 2] ^= 1;  // one face opens or closes
  EXPECT_TRUE(update_fluid_regions(c.grid, c.closed, c.boundary, got));
  EXPECT_EQ(got.region, reference(c).region);
  EXPECT_EQ(got.enclosed, reference(c).enclosed);

  c.boundary.side(0, 0).type = BoundaryType::Open;  // a side opens
  EXPECT_TRUE(update_fluid_regions(c.grid, c.closed, c.boundary, got));
  EXPECT_EQ(got.enclosed, reference(c).enclosed);

  // The plain labelling in between forgets the key; water is never kept.
  label_fluid_regions(c.grid, c.closed, c.boundary, got);
  EXPECT_TRUE(update_fluid_regions(c.grid, c.closed, c.boundary, got));
  const Case wet = random_case({9, 7, 8}, 0.35, 0.3, 6);
  const std::span<const std::uint8_t> liquid(wet.liquid);
  EXPECT_TRUE(update_fluid_regions(wet.grid, wet.closed, wet.boundary, got, true, liquid));
  EXPECT_TRUE(update_fluid_regions(wet.grid, wet.closed, wet.boundary, got, true, liquid));
  EXPECT_EQ(got.region, reference(wet).region);
}

}  // namespace
}  // namespace shellflow::grid_fluid
