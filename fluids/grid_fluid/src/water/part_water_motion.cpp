#include "shellflow/grid_fluid/water/part_water_motion.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "shellflow/grid_fluid/water/level_set_advector.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {

/// Where a sample of water lands: a part of `after` (its cell then unused) or a whole cell.
struct Landing {
  std::int32_t part = -1;
  std::int64_t cell = -1;
  double distance = 0.0;  ///< from the shell, before the move
  bool wet = false;       ///< the level set after the move shows water there
};

void add_water(const CellParts& after, VolumeFraction& fraction, std::int32_t part,
               std::int64_t cell, double water) {
  if (part >= 0 && !after.parts()[part].slot)
    fraction.part_values()[part] += water;
  else
    fraction.values()[part >= 0 ? after.parts()[part].cell : cell] += water;
}

/// `normal` (a unit normal of the triangle of `hit` in `before`) turned with the triangle into
/// `after`.
Eigen::Vector3d turned_normal(const ShellGeometry& before, const ShellGeometry& after,
                              const geometry::WedgeHit& hit, const Eigen::Vector3d& normal) {
  const auto plane = [&](const ShellGeometry& shells) {
    const geometry::TriangleCorners c = shells.mesh(hit.shell).corners(hit.triangle);
    return Eigen::Vector3d((c[1] - c[0]).cross(c[2] - c[0]));
  };
  const Eigen::Vector3d was = plane(before), now = plane(after);
  if (now.squaredNorm() == 0.0) return normal;
  return was.dot(normal) >= 0.0 ? now.normalized() : Eigen::Vector3d(-now.normalized());
}

/// Whether `cell` has the same parts (the same corner groups) in `before` and `after`.
bool same_parts(const CellParts& before, const CellParts& after, std::int64_t cell) {
  const auto old_parts = before.parts_of(cell), new_parts = after.parts_of(cell);
  return old_parts.size() == new_parts.size() &&
         std::equal(old_parts.begin(), old_parts.end(), new_parts.begin(),
                    [](const CellPart& p, const CellPart& q) { return p.corners == q.corners; });
}

}  // namespace

void carry_part_water(const grid::UniformGrid& grid, const CellParts& before,
                      std::span<const double> water_before, const ShellGeometry& shells_before,
                      const CellParts& after, const ShellGeometry& shells_after,
                      const LevelSet& level_set, VolumeFraction& fraction) {
  constexpr int kSamples = 4;  // per axis, as the first share of a cut cell's water
  const double dx = grid.dx(), h = dx / kSamples;
  const double off = 2.0 * shells_after.epsilon();  // a point beside a shell, past its wedge
  const LevelSetAdvector visible(level_set.grid());
  const auto old_parts = before.parts();
  std::vector<Landing> landings;
  std::vector<Eigen::Vector3d> samples;
  for (size_t p = 0; p < old_parts.size(); ++p) {
    const CellPart& part = old_parts[p];
    const double water = water_before[p];
    if (water <= 0.0) continue;
    if (same_parts(before, after, part.cell)) {
      const auto now = after.parts_of(part.cell);
      const auto same = std::find_if(now.begin(), now.end(),
                                     [&](const CellPart& q) { return q.corners == part.corners; });
      add_water(after, fraction, static_cast<std::int32_t>(&*same - after.parts().data()),
                part.cell, water);
      continue;
    }
    landings.clear();
    // The part's samples: the 4³ of its cell that see it, or, a part too small for them (a
    // sliver the shell is leaving), its corners.
    const Eigen::Vector3d low = CellParts::corner_position(grid, part.cell, 0);
    samples.clear();
    for (int k = 0; k < kSamples; ++k)
      for (int j = 0; j < kSamples; ++j)
        for (int i = 0; i < kSamples; ++i) {
          const Eigen::Vector3d x = low + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
          if (before.part_seen_from(shells_before, grid, part.cell, x) == static_cast<int>(p))
            samples.push_back(x);
        }
    if (samples.empty())
      for (int c = 0; c < 8; ++c)
        if (part.corners >> c & 1u)
          samples.push_back(CellParts::corner_position(grid, part.cell, c));
    for (const Eigen::Vector3d& x : samples) {
      // The sample rides its nearest shell point, and must then still see that point's side.
      Landing landing;
      Eigen::Vector3d moved = x;
      if (const auto contact = shells_before.nearest(x, 2.0 * dx, x)) {
        landing.distance = contact->distance;
        const auto then = shells_after.point_at(contact->where);
        if (!then) continue;
        moved += *then - contact->point;
        const Eigen::Vector3d side = *then + off * turned_normal(shells_before, shells_after,
                                                                 contact->where, contact->normal);
        if (!shells_after.visible(moved, side)) continue;
      }
      Eigen::Vector3i at;
      for (int a = 0; a < 3; ++a)
        at[a] = static_cast<int>(std::floor((moved[a] - grid.origin()[a]) / dx));
      if (!grid.contains(Location::Cell, at)) continue;
      landing.cell = grid.index(Location::Cell, at);
      if (!after.parts_of(landing.cell).empty()) {
        landing.part = after.part_seen_from(shells_after, grid, landing.cell, moved);
        if (landing.part < 0) continue;  // in a wedge, or a pocket with no corner
      }
      const auto phi = visible.sample_visible(level_set.phi(), moved, shells_after);
      landing.wet = phi && *phi <= 0.0;
      landings.push_back(landing);
    }
    const auto wet =
        std::count_if(landings.begin(), landings.end(), [](const Landing& l) { return l.wet; });
    if (wet == 0 && !landings.empty()) {
      // A film the level set does not show lies against its shell: the samples nearest it,
      // as many as its share of the part.
      std::sort(landings.begin(), landings.end(),
                [](const Landing& a, const Landing& b) { return a.distance < b.distance; });
      const double fill = part.volume > 0.0 ? water / part.volume : 1.0;
      const auto count =
          std::clamp<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(std::ceil(fill * landings.size())),
                                     1, static_cast<std::ptrdiff_t>(landings.size()));
      for (std::ptrdiff_t l = 0; l < count; ++l) landings[l].wet = true;
    }
    const auto carried =
        std::count_if(landings.begin(), landings.end(), [](const Landing& l) { return l.wet; });
    if (carried > 0) {
      for (const Landing& l : landings)
        if (l.wet) add_water(after, fraction, l.part, l.cell, water / carried);
      continue;
    }
    // No sample landed: the part of the cell holding most of its corners keeps it (the slot
    // among equals; a cell now whole, itself).
    std::int32_t best = -1;
    int best_score = -1;
    for (const CellPart& q : after.parts_of(part.cell)) {
      const int score = 2 * std::popcount(static_cast<unsigned>(q.corners & part.corners)) + q.slot;
      if (score > best_score) {
        best_score = score;
        best = static_cast<std::int32_t>(&q - after.parts().data());
      }
    }
    add_water(after, fraction, best, part.cell, water);
  }
}

}  // namespace shellflow::grid_fluid
