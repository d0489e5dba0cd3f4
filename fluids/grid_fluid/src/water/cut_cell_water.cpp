#include "shellflow/grid_fluid/water/cut_cell_water.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>

#include "shellflow/geometry/triangle_mesh.hpp"
#include "shellflow/grid_fluid/water/level_set_advector.hpp"
#include "shellflow/grid_fluid/water/part_water_motion.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {
// Water the level set does not show is a film, liquid, from this share of its cell (a film
// a thousandth of a cell thick across it); less is a trace the pressure does not see.
constexpr double kFilm = 1e-3;
/// A fragment with less of its face than this is a sliver: the velocity the nodes and the
/// step's CFL read there is its face's (F still moves with the projection's, which it barely
/// carries).
constexpr double kSliver = 1e-3;
}  // namespace

void CutCellWater::update(sdk::ShellSet shells, const ShellGeometry& geometry,
                          const ShellGeometry* previous, const MacGrid& mac,
                          const LevelSet& level_set, VolumeFraction& fraction) {
  if (m_parts) {
    bool still = shells.size() == m_positions.size();
    for (size_t s = 0; still && s < shells.size(); ++s)
      still = shells[s].positions.rows() == m_positions[s].rows() &&
              (shells[s].positions.array() == m_positions[s].array()).all();
    if (still) return;
    if (previous == nullptr)
      throw Error(
          "/fluid/water/cut_cells: the shells moved between two steps of the fluid (a step "
          "began where the last one did not end); the parts' water cannot be carried");
  }
  geometry::ShellBand band(m_grid);
  m_positions.clear();
  for (const auto& shell : shells) {
    m_positions.push_back(shell.positions);
    if (shell.triangle_count() > 0) band.add(geometry::TriangleMesh(shell), 2.0 * m_grid.dx());
  }
  std::unique_ptr<CellParts> before = std::move(m_parts);
  m_parts = std::make_unique<CellParts>(geometry, band);
  m_pieces = shell_pieces(geometry, m_grid, *m_parts);
  m_shell_flux.assign(m_parts->parts().size(), Eigen::Vector3d::Zero());
  std::vector<double> water;  // each old part's, its cell's slot emptied
  if (before) {
    const auto old = before->parts();
    water.resize(old.size());
    for (size_t p = 0; p < old.size(); ++p)
      water[p] = old[p].slot ? fraction.values()[old[p].cell] : fraction.part_values()[p];
    for (const CellPart& part : old)
      if (part.slot) fraction.values()[part.cell] = 0.0;
  }
  m_fragments = carry_fragments(before.get(), mac);
  m_projected = m_fragments;
  m_cut_faces = CutFaces{m_parts.get(), &m_fragments};
  fraction.set_cut_cells(m_parts.get(), &m_projected, &m_shell_flux);
  share_water(geometry, level_set, fraction, before.get());
  if (before)
    carry_part_water(m_grid, *before, water, *previous, *m_parts, geometry, level_set, fraction);
}

FragmentVelocities CutCellWater::carry_fragments(const CellParts* before,
                                                 const MacGrid& mac) const {
  FragmentVelocities carried = m_parts->still_fragments();
  for (int a = 0; a < 3; ++a)
    for (const FaceSplit& split : m_parts->split_faces(a)) {
      const FaceSplit* old = before != nullptr ? before->split(a, split.face) : nullptr;
      const auto list = m_parts->fragments_of(a, split);
      for (size_t k = 0; k < list.size(); ++k) {
        double velocity = mac.face_velocity(a)[split.face];
        int most = 0;
        if (old != nullptr)
          for (int o = 0; o < old->count; ++o) {
            const auto& fragment = before->fragments_of(a, *old)[o];
            const int shared = std::popcount(unsigned(fragment.corners & list[k].corners));
            if (shared > most) {
              most = shared;
              velocity = m_fragments[a][old->first + o];
            }
          }
        carried[a][split.first + k] = velocity;
      }
    }
  return carried;
}

const std::vector<Eigen::Vector3d>& CutCellWater::shell_flux(const ShellGeometry& geometry) {
  m_shell_flux = grid_fluid::shell_flux(geometry, m_pieces, m_parts->parts().size());
  return m_shell_flux;
}

void CutCellWater::share_water(const ShellGeometry& geometry, const LevelSet& level_set,
                               VolumeFraction& fraction, const CellParts* before) const {
  constexpr int kSamples = 4;
  const double dx = m_grid.dx(), h = dx / kSamples;  // the samples' spacing
  const auto all = m_parts->parts();
  std::vector<double> share(all.size(), 0.0);
  std::vector<int> found(all.size(), 0);  // the samples each part sees, wet or dry
  const LevelSetAdvector visible(level_set.grid());
  for (size_t first = 0; first < all.size();) {
    const std::int64_t cell = all[first].cell;
    size_t last = first;
    while (last < all.size() && all[last].cell == cell) ++last;
    const double water = fraction.values()[cell];
    if (water > 0.0 && (before == nullptr || before->parts_of(cell).empty())) {
      const Eigen::Vector3d low =
          m_grid.position(Location::Cell, cell) - Eigen::Vector3d::Constant(0.5 * dx);
      double seen = 0.0;
      for (int k = 0; k < kSamples; ++k)
        for (int j = 0; j < kSamples; ++j)
          for (int i = 0; i < kSamples; ++i) {
            const Eigen::Vector3d x = low + h * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
            const int p = m_parts->part_seen_from(geometry, m_grid, cell, x);
            if (p < 0) continue;
            // Water by the sign of φ as the sample sees it: the lattice samples across a shell
            // (a dam where the water ends) continued from the sample's own side.
            const auto phi = visible.sample_visible(level_set.phi(), x, geometry);
            const double wet = phi && *phi <= 0.0 ? 1.0 : 0.0;
            ++found[p];
            share[p] += wet;
            seen += wet;
          }
      // A part too small for the samples to find (a corner cut off, a sliver a shell swept
      // into the cell) reads its corners, each wet by φ as it sees it, in proportion to its
      // volume; the cell's water is then shared in proportion, its total kept.
      for (size_t p = first; p < last; ++p) {
        if (found[p] != 0) continue;
        int corners = 0, wet = 0;
        for (int c = 0; c < 8; ++c) {
          if (!(all[p].corners >> c & 1u)) continue;
          const Eigen::Vector3d x = CellParts::corner_position(m_grid, cell, c);
          const auto phi = visible.sample_visible(level_set.phi(), x, geometry);
          ++corners;
          wet += phi && *phi <= 0.0 ? 1 : 0;
        }
        share[p] =
            corners > 0 ? all[p].volume * kSamples * kSamples * kSamples * wet / corners : 0.0;
        seen += share[p];
      }
      for (size_t p = first; p < last; ++p) {
        const double part_water =
            seen > 0.0 ? water * share[p] / seen : (all[p].slot ? water : 0.0);
        if (all[p].slot)
          fraction.values()[cell] = part_water;
        else
          fraction.part_values()[p] = part_water;
      }
    }
    first = last;
  }
}

const std::vector<double>& CutCellWater::part_phi(const ShellGeometry& geometry,
                                                  std::span<const double> cell_phi,
                                                  VolumeFraction& fraction) {
  const auto parts = m_parts->parts();
  const double dx = m_grid.dx();
  std::vector<std::uint8_t> liquid(parts.size(), 0);
  continue_level_set(cell_phi);
  const auto water_of = [&](size_t p) {
    return parts[p].slot ? fraction.values()[parts[p].cell] : fraction.part_values()[p];
  };
  // A part holding no water that φ continued from air alone reads water only where the level
  // set beyond it measured its distance through a shell to the water on the other side (just
  // outside a cup's wall): air, as near the surface as its nearest neighbour. Columns of such
  // slivers along a cup's wall were liquid with nothing holding them and fell freely.
  for (size_t p = 0; p < parts.size(); ++p) {
    if (m_part_phi[p] <= 0.0 && m_air_around[p] > 0.0 && water_of(p) <= kFilm)
      m_part_phi[p] = m_air_around[p];
    liquid[p] = m_part_phi[p] <= 0.0 ? 1 : 0;
  }
  // Water the level set shows as air with no liquid beside it on its side is a film it lost,
  // and a part F fills half or more is water whatever the level set continued into it (as
  // F's correction makes a whole cell): liquid, its φ from the plane parallel to its shell
  // that holds its water. A part holding a little of a deep neighbour's surface is that
  // surface's, as a whole cell would be.
  const auto beside = liquid_beside(cell_phi, liquid);
  for (size_t p = 0; p < parts.size(); ++p) {
    const CellPart& part = parts[p];
    const double water = water_of(p);
    if (liquid[p] || water <= kFilm) continue;
    if (beside[p] && water < 0.5 * part.volume) continue;
    const auto film = film_surface(geometry, part, water);
    if (!film) continue;
    // An extra's centre lies behind its shell, in the film's half-space; a slot's in its water
    // is that deep, or, above its film, held at the film's depth below it.
    const double depth = !part.slot           ? film->height
                         : film->height > 0.0 ? film->height
                                              : film->height - film->shell;
    m_part_phi[p] = -depth * dx;
    liquid[p] = 1;
  }
  fraction.set_liquid_parts(std::move(liquid));
  return m_part_phi;
}

void CutCellWater::continue_level_set(std::span<const double> cell_phi) {
  const auto parts = m_parts->parts();
  m_part_phi.resize(parts.size());
  m_air_around.assign(parts.size(), 0.0);
  std::vector<std::uint8_t> known(parts.size(), 0);
  for (size_t p = 0; p < parts.size(); ++p)
    if (parts[p].holds_centre) {  // a centre on a shell is no part's: its slot is continued
      m_part_phi[p] = cell_phi[parts[p].cell];
      known[p] = 1;
    }
  // Each pass continues φ into the parts not yet reached from the parts and whole cells its
  // fragments reach that are (the first: the whole cells and the parts holding their centres;
  // then a pocket between shells from the far parts beside it). Along a fragment's axis, φ
  // continued linearly from the neighbour and the level set's sample beyond it (exact for a plane
  // surface).
  struct Side {
    double sum = 0.0;
    int count = 0;
    // The least φ of the neighbours it is continued from.
    double nearest = std::numeric_limits<double>::infinity();
  };
  std::vector<Side> side(parts.size());
  constexpr int kMostPasses = 8;  // a pocket this many parts from a whole cell stays air
  for (int pass = 0; pass < kMostPasses; ++pass) {
    for (int a = 0; a < 3; ++a) {
      const Location loc = face_location(a);
      for (const FaceSplit& split : m_parts->split_faces(a)) {
        const Eigen::Vector3i ijk = m_grid.coordinates(loc, split.face);
        const auto cells = cells_beside(m_grid, a, split.face);
        // The samples one cell farther on either side (none at the domain's sides).
        std::int64_t farther[2] = {-1, -1};
        if (ijk[a] >= 2) {
          Eigen::Vector3i f = ijk;
          f[a] -= 2;
          farther[0] = m_grid.index(Location::Cell, f);
        }
        if (ijk[a] + 1 < m_grid.cells()[a]) {
          Eigen::Vector3i f = ijk;
          f[a] += 1;
          farther[1] = m_grid.index(Location::Cell, f);
        }
        for (const FaceFragment& fragment : m_parts->fragments_of(a, split)) {
          const std::int32_t ends[2] = {fragment.minus, fragment.plus};
          for (int e = 0; e < 2; ++e) {
            const std::int32_t mine = ends[e], other = ends[1 - e];
            if (mine < 0 || known[mine] || (other >= 0 && known[other] != 1)) continue;
            const double phi = other >= 0 ? m_part_phi[other] : cell_phi[cells[1 - e]];
            const std::int64_t far = farther[1 - e];
            side[mine].sum += far >= 0 ? 2.0 * phi - cell_phi[far] : phi;
            ++side[mine].count;
            side[mine].nearest = std::min(side[mine].nearest, phi);
          }
        }
      }
    }
    bool reached = false, unreached = false;
    for (size_t p = 0; p < parts.size(); ++p)
      if (!known[p] && side[p].count > 0) {
        m_part_phi[p] = side[p].sum / side[p].count;
        m_air_around[p] = side[p].nearest > 0.0 ? side[p].nearest : 0.0;
        known[p] = 2;  // read from the next pass on
        reached = true;
      } else if (!known[p]) {
        unreached = true;
      }
    if (!reached || !unreached) break;  // most scenes: every part in the first pass
    for (auto& k : known) k = k != 0 ? 1 : 0;
  }
  for (size_t p = 0; p < parts.size(); ++p)
    if (!known[p]) m_part_phi[p] = 0.5 * m_grid.dx();  // no water or air reaches it: air
}

std::vector<std::uint8_t> CutCellWater::liquid_beside(std::span<const double> cell_phi,
                                                      std::span<const std::uint8_t> liquid) const {
  const auto parts = m_parts->parts();
  std::vector<std::uint8_t> beside(parts.size(), 0);
  const auto liquid_at = [&](std::int32_t part, std::int64_t cell) {
    return part >= 0 ? liquid[part] != 0 : cell >= 0 && cell_phi[cell] <= 0.0;
  };
  for (int a = 0; a < 3; ++a)
    for (const FaceSplit& split : m_parts->split_faces(a)) {
      const auto [minus, plus] = cells_beside(m_grid, a, split.face);
      for (const FaceFragment& fragment : m_parts->fragments_of(a, split)) {
        if (fragment.minus >= 0 && liquid_at(fragment.plus, plus)) beside[fragment.minus] = 1;
        if (fragment.plus >= 0 && liquid_at(fragment.minus, minus)) beside[fragment.plus] = 1;
      }
    }
  // A slot's faces no shell splits join it to whole cells or to other slots.
  for (size_t p = 0; p < parts.size(); ++p) {
    if (!parts[p].slot || beside[p]) continue;
    const Eigen::Vector3i ijk = m_grid.coordinates(Location::Cell, parts[p].cell);
    for (int a = 0; a < 3 && !beside[p]; ++a)
      for (int side = 0; side < 2 && !beside[p]; ++side) {
        Eigen::Vector3i face = ijk, next = ijk;
        face[a] += side;
        next[a] += side ? 1 : -1;
        if (next[a] < 0 || next[a] >= m_grid.cells()[a]) continue;
        if (m_parts->split(a, m_grid.index(face_location(a), face)) != nullptr) continue;
        beside[p] = cell_phi[m_grid.index(Location::Cell, next)] <= 0.0 ? 1 : 0;
      }
  }
  return beside;
}

std::optional<CutCellWater::FilmSurface> CutCellWater::film_surface(const ShellGeometry& geometry,
                                                                    const CellPart& part,
                                                                    double water) const {
  const double dx = m_grid.dx();
  const Eigen::Vector3d centre = m_grid.position(Location::Cell, part.cell);
  const auto contact = geometry.nearest(centre, std::sqrt(3.0) * dx, centre);
  if (!contact) return std::nullopt;
  // The shell's plane, its normal towards the part's corners.
  Eigen::Vector3d normal = contact->normal;
  const Eigen::Vector3d corner =
      CellParts::corner_position(m_grid, part.cell, std::countr_zero(unsigned(part.corners)));
  if (normal.dot(corner - contact->point) < 0.0) normal = -normal;
  FilmSurface film;
  film.shell = normal.dot(contact->point - centre) / dx;
  const Eigen::Vector3d lo = Eigen::Vector3d::Constant(-0.5), hi = Eigen::Vector3d::Constant(0.5);
  const double beyond = VolumeFraction::box_fraction_below(normal, film.shell, lo, hi);
  film.height = VolumeFraction::plane_height(normal, std::min(beyond + water, 1.0));
  return film;
}

void CutCellWater::extrapolate_fragments(const MacGrid& mac, std::span<const double> cell_phi) {
  // As a face's (Liquid::extrapolate): a fragment whose two ends' mean φ is water keeps the
  // projection's value; one nearer the air (θ < ½ beside a liquid part, where the ghost-fluid
  // update grows as 1/θ) takes its face's extrapolated velocity, as does a sliver of a face
  // (the solve sees its flux, not its speed: one by a shaken cup's wall reached 129 m/s). F
  // moves with the projection's fragments beside a liquid end (divergence free), and with the
  // extrapolated ones between two air ends, which the projection did not touch (an air part
  // filling from a liquid neighbour gives on as a cell in the air does).
  const auto phi = [&](std::int32_t part, std::int64_t cell) {
    return part >= 0 ? m_part_phi[part] : cell_phi[cell];
  };  // a whole cell's φ is the level set's
  for (int a = 0; a < 3; ++a) {
    for (const FaceSplit& split : m_parts->split_faces(a)) {
      const auto [minus, plus] = cells_beside(m_grid, a, split.face);
      const auto list = m_parts->fragments_of(a, split);
      const double extrapolated = mac.face_velocity(a)[split.face];
      for (size_t k = 0; k < list.size(); ++k) {
        const double phi_minus = phi(list[k].minus, minus), phi_plus = phi(list[k].plus, plus);
        double& fragment = m_fragments[a][split.first + k];
        m_projected[a][split.first + k] =
            phi_minus > 0.0 && phi_plus > 0.0 ? extrapolated : fragment;
        if (phi_minus + phi_plus > 0.0 || list[k].aperture < kSliver) fragment = extrapolated;
      }
    }
  }
}

}  // namespace shellflow::grid_fluid
