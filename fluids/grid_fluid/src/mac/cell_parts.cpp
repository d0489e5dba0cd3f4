#include "shellflow/grid_fluid/mac/cell_parts.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numeric>
#include <optional>

#include "shellflow/grid_fluid/water/volume_fraction.hpp"

namespace shellflow::grid_fluid {

namespace {

using grid::Location;

// Per node: bit a set when the lattice edge to the next node along axis a touches a wedge,
// kInWedge when the node itself lies in one.
constexpr std::uint8_t kInWedge = 8;
// Lines per axis across a cell (3²) or a face (4) where no single plane holds the shells near
// it: each line is split exactly at the shells it crosses (the midpoint rule across the lines).
constexpr int kCellLines = 3;
constexpr int kFaceLines = 4;

struct Plane {
  Eigen::Vector3d normal;  ///< unit
  Eigen::Vector3d point;
};

/// The plane holding, within `tolerance`, every triangle whose box meets `box`; none when
/// no triangle does or two planes are needed (two shells, a fold, a curved sheet).
std::optional<Plane> single_plane(const ShellGeometry& shells, const geometry::Aabb& box,
                                  double tolerance) {
  std::optional<Plane> plane;
  bool planar = true;
  for (int s = 0; s < shells.shell_count() && planar; ++s) {
    const geometry::TriangleBvh& bvh = shells.bvh(s);
    const auto prepared = bvh.prepared_triangles();
    bvh.triangles_overlapping(box, [&](int t) {
      const geometry::PreparedTriangle& tri = prepared[t];
      if (tri.degenerate) return false;  // a segment or a point: no plane, in any plane
      if (!plane) {
        plane = Plane{tri.unit_normal, tri.corners[0]};
        return false;
      }
      for (const Eigen::Vector3d& c : tri.corners)
        if (std::abs(plane->normal.dot(c - plane->point)) > tolerance) {
          planar = false;
          return true;
        }
      return false;
    });
  }
  if (!planar) return std::nullopt;
  return plane;
}

/// The groups of `count` corners joined by the listed edges (pairs of corner numbers); a
/// corner not in `free_corners` joins none. Each group as a bit mask, in ascending order.
template <int count, size_t edges>
std::vector<std::uint8_t> corner_groups(std::uint8_t free_corners,
                                        const std::array<std::array<int, 2>, edges>& edge,
                                        const std::array<bool, edges>& blocked) {
  std::array<int, count> root;
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int c) {
    while (root[c] != c) c = root[c] = root[root[c]];
    return c;
  };
  for (size_t e = 0; e < edges; ++e) {
    const int p = edge[e][0], q = edge[e][1];
    if (blocked[e] || !(free_corners >> p & 1u) || !(free_corners >> q & 1u)) continue;
    root[find(p)] = find(q);
  }
  std::array<std::uint8_t, count> mask{};
  for (int c = 0; c < count; ++c)
    if (free_corners >> c & 1u) mask[find(c)] |= std::uint8_t(1u << c);
  std::vector<std::uint8_t> groups;
  for (int c = 0; c < count; ++c)
    if (mask[c] != 0) groups.push_back(mask[c]);
  std::sort(groups.begin(), groups.end());
  return groups;
}

/// The 12 edges of a cell as pairs of corners; edge 4a + k runs along axis a.
std::array<std::array<int, 2>, 12> cell_edges() {
  std::array<std::array<int, 2>, 12> edges{};
  int e = 0;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 8; ++c)
      if (!(c >> a & 1)) edges[e++] = {c, c | (1 << a)};
  return edges;
}

/// Whether each group's corners lie strictly on one side of `plane`, no two groups on the same
/// side; `side[g]` is then +1 or −1.
bool plane_parts_groups(const Plane& plane, std::span<const std::uint8_t> groups,
                        std::span<const Eigen::Vector3d> corner_position,
                        std::array<int, 8>& side) {
  if (groups.size() > 2) return false;
  for (size_t g = 0; g < groups.size(); ++g) {
    int sign = 0;
    for (size_t c = 0; c < corner_position.size(); ++c) {
      if (!(groups[g] >> c & 1u)) continue;
      const double d = plane.normal.dot(corner_position[c] - plane.point);
      const int s = d > 0.0 ? 1 : d < 0.0 ? -1 : 0;
      if (s == 0 || (sign != 0 && s != sign)) return false;
      sign = s;
    }
    side[g] = sign;
  }
  return groups.size() < 2 || side[0] != side[1];
}

/// The group of the nearest free corner that `x` sees, or −1 (x in a wedge, or in a pocket
/// that holds no corner).
int group_seen_from(const ShellGeometry& shells, const Eigen::Vector3d& x,
                    std::span<const Eigen::Vector3d> corner_position,
                    std::span<const std::uint8_t> groups) {
  // The corners nearest first (an insertion sort of at most 8).
  const int n = static_cast<int>(std::min<size_t>(corner_position.size(), 8));
  std::array<int, 8> order{};
  std::array<double, 8> distance{};
  for (int c = 0; c < n; ++c) {
    const double d = (corner_position[c] - x).squaredNorm();
    int k = c;
    for (; k > 0 && distance[k - 1] > d; --k) {
      order[k] = order[k - 1];
      distance[k] = distance[k - 1];
    }
    order[k] = c;
    distance[k] = d;
  }
  for (int k = 0; k < n; ++k) {
    const int c = order[k];
    for (size_t g = 0; g < groups.size(); ++g)
      if ((groups[g] >> c & 1u) && shells.visible(x, corner_position[c]))
        return static_cast<int>(g);
  }
  return -1;
}

/// Adds `weight` times each group's share of the segment [from, to] to `shares`: the segment is
/// split where it crosses the shells, each piece given to the group its midpoint sees.
void add_line_shares(const ShellGeometry& shells, const Eigen::Vector3d& from,
                     const Eigen::Vector3d& to, std::span<const Eigen::Vector3d> corner_position,
                     std::span<const std::uint8_t> groups, double weight,
                     std::vector<double>& shares) {
  const double length = (to - from).norm();
  const double step = shells.epsilon() / length;  // a wedge's thickness, in the segment's parameter
  const auto at = [&](double t) { return Eigen::Vector3d(from + t * (to - from)); };
  double start = 0.0, cast_from = 0.0;  // the piece starts at a crossing, the cast past its wedge
  while (start < 1.0) {
    double end = 1.0;
    if (const auto hit = shells.first_hit(at(cast_from), to))
      end = cast_from + hit->s * (1.0 - cast_from);
    if (end > start) {
      const int g = group_seen_from(shells, at(0.5 * (start + end)), corner_position, groups);
      if (g >= 0) shares[g] += weight * (end - start);
    }
    // Past the wedge the segment met (thicker along an oblique segment: step again).
    start = end;
    cast_from = end + step;
    for (int k = 0; k < 64 && cast_from < 1.0 && shells.caster().inside(at(cast_from)); ++k)
      cast_from += step;
    if (cast_from >= 1.0) {  // the segment ends in the wedge: the rest is one piece
      if (start < 1.0) {
        const int g = group_seen_from(shells, at(0.5 * (start + 1.0)), corner_position, groups);
        if (g >= 0) shares[g] += weight * (1.0 - start);
      }
      break;
    }
  }
}

}  // namespace

std::array<std::int64_t, 2> cells_beside(const grid::UniformGrid& grid, int axis,
                                         std::int64_t face) {
  const Eigen::Vector3i ijk = grid.coordinates(face_location(axis), face);
  Eigen::Vector3i below = ijk;
  below[axis] -= 1;
  return {below[axis] >= 0 ? grid.index(Location::Cell, below) : -1,
          ijk[axis] < grid.cells()[axis] ? grid.index(Location::Cell, ijk) : -1};
}

double max_fragment_speed(const FragmentVelocities& fragments) {
  double fastest = 0.0;
  for (const auto& list : fragments)
    for (const double v : list) fastest = std::max(fastest, std::abs(v));
  return fastest;
}

double CellParts::max_filling_speed(const FragmentVelocities& fragments, double smallest) const {
  double fastest = 0.0;
  const auto volume = [&](std::int32_t part) { return part >= 0 ? m_parts[part].volume : 1.0; };
  for (int a = 0; a < 3; ++a)
    for (const FaceSplit& split : m_splits[a])
      for (int k = 0; k < split.count; ++k) {
        const FaceFragment& f = m_fragments[a][split.first + k];
        const double room = std::max(std::min(volume(f.minus), volume(f.plus)), smallest);
        fastest = std::max(fastest, std::abs(fragments[a][split.first + k]) * f.aperture / room);
      }
  return fastest;
}

Eigen::Vector3i CellParts::face_corner(int axis, int corner) {
  Eigen::Vector3i offset = Eigen::Vector3i::Zero();
  offset[(axis + 1) % 3] = corner & 1;
  offset[(axis + 2) % 3] = (corner >> 1) & 1;
  return offset;
}

CellParts::CellParts(const ShellGeometry& shells, const geometry::ShellBand& band) {
  if (shells.empty()) return;
  const grid::UniformGrid& grid = band.grid();
  const double dx = grid.dx();
  const double epsilon = shells.epsilon();
  const Eigen::Vector3i cells = grid.cells();
  const int threads = omp_get_max_threads();

  // Nodes: which lie in a wedge, which edges a wedge touches.
  std::vector<std::uint8_t> node_flags(static_cast<size_t>(grid.size(Location::Node)), 0);
  const auto nodes = band.samples(Location::Node);
  const std::int64_t node_count = static_cast<std::int64_t>(nodes.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < node_count; ++s) {
    const std::int64_t n = nodes[s];
    const Eigen::Vector3i ijk = grid.coordinates(Location::Node, n);
    const Eigen::Vector3d x = grid.position(Location::Node, ijk);
    std::uint8_t flags = shells.caster().inside(x) ? kInWedge : 0;
    for (int a = 0; a < 3; ++a) {
      if (ijk[a] == cells[a]) continue;
      Eigen::Vector3d y = x;
      y[a] += dx;
      if (!shells.visible(x, y)) flags |= std::uint8_t(1u << a);
    }
    node_flags[n] = flags;
  }

  // Cells: those beside a flagged node, grouped into parts where they hold two or more.
  std::vector<std::vector<std::int64_t>> near(threads);
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < node_count; ++s) {
    const std::int64_t n = nodes[s];
    if (node_flags[n] == 0) continue;
    const Eigen::Vector3i ijk = grid.coordinates(Location::Node, n);
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3i cell = ijk - cell_corner(c);
      if ((cell.array() >= 0).all() && (cell.array() < cells.array()).all())
        near[omp_get_thread_num()].push_back(grid.index(Location::Cell, cell));
    }
  }
  std::vector<std::int64_t> candidates;
  for (const auto& list : near) candidates.insert(candidates.end(), list.begin(), list.end());
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());

  const auto edges = cell_edges();
  const auto corner_node = [&](const Eigen::Vector3i& cell, int c) {
    return grid.index(Location::Node, cell + cell_corner(c));
  };
  std::vector<std::vector<CellPart>> found(threads);
  const std::int64_t candidate_count = static_cast<std::int64_t>(candidates.size());
#pragma omp parallel for schedule(dynamic, 64)
  for (std::int64_t k = 0; k < candidate_count; ++k) {
    const std::int64_t cell = candidates[k];
    const Eigen::Vector3i ijk = grid.coordinates(Location::Cell, cell);
    std::uint8_t free_corners = 0;
    std::array<bool, 12> blocked{};
    std::array<Eigen::Vector3d, 8> corner;
    for (int c = 0; c < 8; ++c) {
      if (!(node_flags[corner_node(ijk, c)] & kInWedge)) free_corners |= std::uint8_t(1u << c);
      corner[c] = grid.position(Location::Node, Eigen::Vector3i(ijk + cell_corner(c)));
    }
    for (int e = 0; e < 12; ++e)
      blocked[e] = (node_flags[corner_node(ijk, edges[e][0])] >> (e / 4) & 1u) != 0;
    const auto groups = corner_groups<8>(free_corners, edges, blocked);
    if (groups.size() < 2) continue;  // whole

    const Eigen::Vector3d centre = grid.position(Location::Cell, ijk);
    std::vector<double> volume(groups.size(), 0.0);
    const geometry::Aabb box(centre.array() - (0.5 * dx + epsilon),
                             centre.array() + (0.5 * dx + epsilon));
    const auto plane = single_plane(shells, box, 0.5 * epsilon);
    std::array<int, 8> side{};
    if (plane && plane_parts_groups(*plane, groups, corner, side)) {
      const double below = VolumeFraction::box_fraction_below(
          plane->normal, plane->normal.dot(plane->point - centre) / dx,
          Eigen::Vector3d::Constant(-0.5), Eigen::Vector3d::Constant(0.5));
      for (size_t g = 0; g < groups.size(); ++g) volume[g] = side[g] < 0 ? below : 1.0 - below;
    } else {
      // Columns along the axis nearest the shells' normal there.
      const auto contact = shells.nearest(centre, dx, centre);
      int up = 1;
      if (contact) contact->normal.cwiseAbs().maxCoeff(&up);
      const int u1 = (up + 1) % 3, u2 = (up + 2) % 3;
      for (int i = 0; i < kCellLines; ++i)
        for (int j = 0; j < kCellLines; ++j) {
          Eigen::Vector3d bottom = centre;
          bottom[u1] += dx * ((i + 0.5) / kCellLines - 0.5);
          bottom[u2] += dx * ((j + 0.5) / kCellLines - 0.5);
          bottom[up] -= 0.5 * dx;
          Eigen::Vector3d top = bottom;
          top[up] += dx;
          add_line_shares(shells, bottom, top, corner, groups, 1.0 / (kCellLines * kCellLines),
                          volume);
        }
    }
    const int centre_group = group_seen_from(shells, centre, corner, groups);
    const int slot =
        centre_group >= 0
            ? centre_group
            : static_cast<int>(std::max_element(volume.begin(), volume.end()) - volume.begin());
    for (size_t g = 0; g < groups.size(); ++g)
      found[omp_get_thread_num()].push_back(CellPart{cell, groups[g], volume[g],
                                                     static_cast<int>(g) == centre_group,
                                                     static_cast<int>(g) == slot});
  }
  for (const auto& list : found) m_parts.insert(m_parts.end(), list.begin(), list.end());
  std::sort(m_parts.begin(), m_parts.end(), [](const CellPart& p, const CellPart& q) {
    return p.cell != q.cell ? p.cell < q.cell : p.corners < q.corners;
  });

  // Faces of the cells looked at: fragments where a face is not simply open.
  const std::array<std::array<int, 2>, 4> face_edges = {{{0, 1}, {2, 3}, {0, 2}, {1, 3}}};
  for (int a = 0; a < 3; ++a) {
    const Location loc = static_cast<Location>(static_cast<int>(Location::FaceX) + a);
    const int t1 = (a + 1) % 3, t2 = (a + 2) % 3;
    std::vector<std::int64_t> faces;
    for (const std::int64_t cell : candidates) {
      const Eigen::Vector3i ijk = grid.coordinates(Location::Cell, cell);
      for (int up = 0; up < 2; ++up) {
        Eigen::Vector3i f = ijk;
        f[a] += up;
        if (f[a] > 0 && f[a] < cells[a]) faces.push_back(grid.index(loc, f));
      }
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());

    struct Found {
      FaceSplit split;
      std::vector<FaceFragment> fragments;
    };
    std::vector<std::vector<Found>> found_faces(threads);
    const std::int64_t face_count = static_cast<std::int64_t>(faces.size());
#pragma omp parallel for schedule(dynamic, 64)
    for (std::int64_t k = 0; k < face_count; ++k) {
      const std::int64_t f = faces[k];
      const Eigen::Vector3i ijk = grid.coordinates(loc, f);
      std::uint8_t free_corners = 0;
      std::array<Eigen::Vector3d, 4> corner;
      for (int c = 0; c < 4; ++c) {
        const Eigen::Vector3i node = ijk + face_corner(a, c);
        if (!(node_flags[grid.index(Location::Node, node)] & kInWedge))
          free_corners |= std::uint8_t(1u << c);
        corner[c] = grid.position(Location::Node, node);
      }
      // Edges 0, 1 run along t1 (from corners 0 and 2), edges 2, 3 along t2 (from 0 and 1).
      std::array<bool, 4> blocked{};
      for (int e = 0; e < 4; ++e) {
        const Eigen::Vector3i from = ijk + face_corner(a, face_edges[e][0]);
        blocked[e] = (node_flags[grid.index(Location::Node, from)] >> (e < 2 ? t1 : t2) & 1u) != 0;
      }
      Eigen::Vector3i minus_cell = ijk;
      minus_cell[a] -= 1;
      const auto minus_parts = parts_of(grid.index(Location::Cell, minus_cell));
      const auto plus_parts = parts_of(grid.index(Location::Cell, ijk));
      const bool edges_open =
          std::none_of(blocked.begin(), blocked.end(), [](bool b) { return b; });
      if (free_corners == 0xF && edges_open && minus_parts.empty() && plus_parts.empty())
        continue;  // simply open

      const auto groups = corner_groups<4>(free_corners, face_edges, blocked);
      Found entry;
      entry.split.face = f;
      std::vector<double> aperture(groups.size(), 0.0);
      if (groups.size() == 1 && free_corners == 0xF) {
        aperture[0] = 1.0;
      } else if (!groups.empty()) {
        const Eigen::Vector3d centre = grid.position(loc, ijk);
        Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * dx + epsilon);
        half[a] = epsilon;
        const auto plane =
            single_plane(shells, geometry::Aabb(centre - half, centre + half), 0.5 * epsilon);
        std::array<int, 8> side{};
        if (plane && plane_parts_groups(*plane, groups, corner, side)) {
          const Eigen::Vector3d& n = plane->normal;
          const double offset = n.dot(centre - plane->point) / dx;
          const bool parallel = std::hypot(n[t1], n[t2]) < 1e-9;
          const double positive = open_square_fraction(n[t1], n[t2], offset);
          for (size_t g = 0; g < groups.size(); ++g)
            aperture[g] = parallel ? 1.0 : side[g] > 0 ? positive : 1.0 - positive;
        } else {
          // Lines along the face's axis nearest the shells' normal there.
          const auto contact = shells.nearest(centre, dx, centre);
          const bool along_t1 =
              !contact || std::abs(contact->normal[t1]) >= std::abs(contact->normal[t2]);
          const int along = along_t1 ? t1 : t2, across = along_t1 ? t2 : t1;
          for (int i = 0; i < kFaceLines; ++i) {
            Eigen::Vector3d from = centre;
            from[across] += dx * ((i + 0.5) / kFaceLines - 0.5);
            from[along] -= 0.5 * dx;
            Eigen::Vector3d to = from;
            to[along] += dx;
            add_line_shares(shells, from, to, corner, groups, 1.0 / kFaceLines, aperture);
          }
        }
      }
      for (size_t g = 0; g < groups.size(); ++g) {
        FaceFragment fragment{groups[g], aperture[g], -1, -1};
        const int c = std::countr_zero(static_cast<unsigned>(groups[g]));
        const Eigen::Vector3i offset = face_corner(a, c);
        const auto part_holding = [&](std::span<const CellPart> cell_parts, Eigen::Vector3i off) {
          const int bit = off[0] + 2 * off[1] + 4 * off[2];
          for (const CellPart& part : cell_parts)
            if (part.corners >> bit & 1u) return static_cast<std::int32_t>(&part - m_parts.data());
          return std::int32_t{-1};
        };
        Eigen::Vector3i upper = offset;
        upper[a] = 1;
        fragment.minus = part_holding(minus_parts, upper);
        fragment.plus = part_holding(plus_parts, offset);
        entry.fragments.push_back(fragment);
      }
      found_faces[omp_get_thread_num()].push_back(std::move(entry));
    }
    std::vector<Found> all;
    for (auto& list : found_faces)
      for (auto& entry : list) all.push_back(std::move(entry));
    std::sort(all.begin(), all.end(),
              [](const Found& x, const Found& y) { return x.split.face < y.split.face; });
    for (Found& entry : all) {
      entry.split.first = static_cast<std::int32_t>(m_fragments[a].size());
      entry.split.count = static_cast<std::int32_t>(entry.fragments.size());
      m_fragments[a].insert(m_fragments[a].end(), entry.fragments.begin(), entry.fragments.end());
      m_splits[a].push_back(entry.split);
    }
  }
}

std::span<const CellPart> CellParts::parts_of(std::int64_t cell) const {
  const auto first = std::lower_bound(m_parts.begin(), m_parts.end(), cell,
                                      [](const CellPart& p, std::int64_t c) { return p.cell < c; });
  auto last = first;
  while (last != m_parts.end() && last->cell == cell) ++last;
  return {first, last};
}

int CellParts::part_seen_from(const ShellGeometry& shells, const grid::UniformGrid& grid,
                              std::int64_t cell, const Eigen::Vector3d& x) const {
  const auto own = parts_of(cell);
  if (own.empty()) return -1;
  const Eigen::Vector3i ijk = grid.coordinates(Location::Cell, cell);
  std::array<Eigen::Vector3d, 8> corner;
  for (int c = 0; c < 8; ++c)
    corner[c] = grid.position(Location::Node, Eigen::Vector3i(ijk + cell_corner(c)));
  std::array<std::uint8_t, 8> groups{};  // a cell has at most 8 parts (one per corner)
  for (size_t p = 0; p < own.size(); ++p) groups[p] = own[p].corners;
  const int g = group_seen_from(shells, x, corner, std::span(groups).first(own.size()));
  return g < 0 ? -1 : static_cast<int>(&own[g] - m_parts.data());
}

const FaceSplit* CellParts::split(int axis, std::int64_t face) const {
  const auto& list = m_splits[axis];
  const auto it = std::lower_bound(list.begin(), list.end(), face,
                                   [](const FaceSplit& s, std::int64_t f) { return s.face < f; });
  return it != list.end() && it->face == face ? &*it : nullptr;
}

}  // namespace shellflow::grid_fluid
