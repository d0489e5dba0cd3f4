#include "shellflow/grid_fluid/mac/face_node_transfer.hpp"

#include <algorithm>
#include <limits>
#include <span>

namespace shellflow::grid_fluid {

using grid::Location;

bool fixed_boundary_face(const grid::UniformGrid& grid, const DomainBoundary& boundary, int axis,
                         const Eigen::Vector3i& ijk) {
  if (ijk[axis] == 0) return boundary.side(axis, 0).type != BoundaryType::Open;
  if (ijk[axis] == grid.cells()[axis]) return boundary.side(axis, 1).type != BoundaryType::Open;
  return false;
}

void apply_boundary_velocities(MacGrid& mac, const DomainBoundary& boundary) {
  for (int a = 0; a < 3; ++a) {
    auto& u = mac.face_velocity(a);
    boundary.for_each_closed_face(mac.grid(), a, [&](std::int64_t f, const FaceCondition& cond) {
      u[f] = cond.type == BoundaryType::Inflow ? cond.velocity[a] : 0.0;
    });
  }
}

void FaceNodeTransfer::faces_to_nodes(const MacGrid& mac, NodeFields& nodes,
                                      const ShellGeometry& shells, const geometry::ShellBand* band,
                                      const CutFaces* cut) const {
  // Every node first takes the plain average of the (up to four) faces of each family
  // about it, one node row at a time from whole face rows (contiguous, vectorised: the
  // per-node loop it replaces ran at 2 GB/s, a sixteenth of the machine's bandwidth);
  // then the shell band's nodes are redone with rays. The faces are summed in the order
  // faces_to_nodes_with_rays sums them and divided alike, so a node gets the same bits
  // on either path (a run resumed from a checkpoint labels another band).
  const Eigen::Vector3i cells = m_grid.cells();
  const Eigen::Vector3i node_counts = m_grid.counts(Location::Node);
  const int nx = cells.x();
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < node_counts.z(); ++k)
    for (int j = 0; j < node_counts.y(); ++j) {
      const Eigen::Vector3i node(0, j, k);
      const std::int64_t row =
          std::int64_t(node_counts.x()) * (j + std::int64_t(node_counts.y()) * k);
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const Eigen::Vector3i fc = m_grid.counts(face_location(a));
        const double* u = mac.face_velocity(a).data();
        // The faces (a, b − {1,0}, c − {1,0}) in faces_to_nodes_with_rays' order, each
        // as a face row and an offset along x (−1 for face i − 1 where x is b or c).
        const double* term_row[4];
        int term_dx[4];
        int terms = 0;
        for (int db = -1; db <= 0; ++db)
          for (int dc = -1; dc <= 0; ++dc) {
            Eigen::Vector3i f = node;
            f[b] += db;
            f[c] += dc;
            if ((b != 0 && (f[b] < 0 || f[b] >= cells[b])) ||
                (c != 0 && (f[c] < 0 || f[c] >= cells[c])))
              continue;
            term_row[terms] = u + std::int64_t(fc.x()) * (f.y() + std::int64_t(fc.y()) * f.z());
            term_dx[terms] = b == 0 ? db : (c == 0 ? dc : 0);
            ++terms;
          }
        double* out = nodes.velocity(a).data() + row;
        const auto node_value = [&](int i) {  // any i: the faces inside the grid only
          double sum = 0.0;
          int count = 0;
          for (int t = 0; t < terms; ++t) {
            const int fi = i + term_dx[t];
            if (fi < 0 || fi >= fc.x()) continue;
            sum += term_row[t][fi];
            ++count;
          }
          return count > 0 ? sum / count : 0.0;
        };
        // x-faces: every node of the row sees all its terms; else the row's two ends
        // lose the faces beyond them.
        const int first = a == 0 ? 0 : 1, last = a == 0 ? nx : nx - 1;
        if (a != 0) {
          out[0] = node_value(0);
          out[nx] = node_value(nx);
        }
        // Indexed as row[i + dx] (no pointer is formed before a row's start).
        const double* r0 = term_row[0];
        const int d0 = term_dx[0];
        if (terms == 4) {
          const double *r1 = term_row[1], *r2 = term_row[2], *r3 = term_row[3];
          const int d1 = term_dx[1], d2 = term_dx[2], d3 = term_dx[3];
          for (int i = first; i <= last; ++i)
            out[i] = (((r0[i + d0] + r1[i + d1]) + r2[i + d2]) + r3[i + d3]) / 4.0;
        } else if (terms == 2) {
          const double* r1 = term_row[1];
          const int d1 = term_dx[1];
          for (int i = first; i <= last; ++i) out[i] = (r0[i + d0] + r1[i + d1]) / 2.0;
        } else {
          for (int i = first; i <= last; ++i) out[i] = node_value(i);
        }
      }
    }
  if (band == nullptr || shells.empty()) return;  // no shell: every face is seen
  const std::span<const std::int64_t> near = band->samples(Location::Node);
  const std::int64_t m = static_cast<std::int64_t>(near.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::int64_t s = 0; s < m; ++s) faces_to_nodes_with_rays(mac, nodes, shells, near[s], cut);
}

void FaceNodeTransfer::faces_to_nodes_with_rays(const MacGrid& mac, NodeFields& nodes,
                                                const ShellGeometry& shells, std::int64_t node,
                                                const CutFaces* cut) const {
  const Eigen::Vector3i ijk = m_grid.coordinates(Location::Node, node);
  const Eigen::Vector3d x = m_grid.position(Location::Node, ijk);
  for (int a = 0; a < 3; ++a) {
    const Location loc = face_location(a);
    const int b = (a + 1) % 3;
    const int c = (a + 2) % 3;
    const auto& u = mac.face_velocity(a);
    double sum = 0.0;
    int terms = 0;
    Eigen::Vector3d object_sum = Eigen::Vector3d::Zero();
    int object_terms = 0;
    // The faces of family a around node ijk: (i_a, i_b - {1,0}, i_c - {1,0}).
    for (int db = -1; db <= 0; ++db) {
      for (int dc = -1; dc <= 0; ++dc) {
        Eigen::Vector3i f = ijk;
        f[b] += db;
        f[c] += dc;
        if (f[b] < 0 || f[c] < 0 || f[b] >= m_grid.cells()[b] || f[c] >= m_grid.cells()[c])
          continue;
        const Eigen::Vector3d y = m_grid.position(loc, f);
        const std::int64_t face = m_grid.index(loc, f);
        const FaceSplit* split = cut != nullptr ? cut->parts->split(a, face) : nullptr;
        if (split != nullptr) {  // the fragment holding this corner, if any
          const FaceFragment* fragment = cut->parts->fragment_holding(a, *split, -db + 2 * -dc);
          if (fragment != nullptr) {
            sum += (*cut->velocities)[a][split->first +
                                         (fragment - cut->parts->fragments_of(a, *split).data())];
            ++terms;
            continue;
          }
        } else if (shells.visible(x, y)) {
          sum += u[face];
          ++terms;
          continue;
        }
        object_sum += shells.object_velocity(x, y);
        ++object_terms;
      }
    }
    double value = 0.0;
    if (terms > 0) {
      value = sum / terms;
    } else if (object_terms > 0) {
      value = object_sum[a] / object_terms;  // §4.2: no visible face
    }
    nodes.velocity(a)[node] = value;
  }
}

void FaceNodeTransfer::mark_held_nodes(const DomainBoundary& boundary, int axis) {
  HeldNodes& held = m_held[axis];
  for (const std::int64_t v : held.flagged) held.flag[v] = 0;
  held.flagged.clear();
  held.faces = grid::IndexBox{Eigen::Vector3i::Zero(), -Eigen::Vector3i::Ones()};
  const auto& faces = boundary.source_faces(axis);
  if (faces.empty()) return;
  held.flag.resize(m_grid.size(Location::Node), 0);
  const Location loc = face_location(axis);
  const int b = (axis + 1) % 3;
  const int c = (axis + 2) % 3;
  Eigen::Vector3i lo = Eigen::Vector3i::Constant(std::numeric_limits<int>::max());
  Eigen::Vector3i hi = Eigen::Vector3i::Constant(std::numeric_limits<int>::min());
  for (const SourceFace& sf : faces) {
    const Eigen::Vector3i f = m_grid.coordinates(loc, sf.face);
    for (int m = 0; m < 4; ++m) {  // its corners: (i_b + {0,1}, i_c + {0,1})
      Eigen::Vector3i v = f;
      v[b] += m & 1;
      v[c] += m >> 1;
      const std::int64_t node = m_grid.index(Location::Node, v);
      if (held.flag[node] != 0) continue;
      held.flag[node] = 1;
      held.flagged.push_back(node);
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  }
  // A face of family a has corners (i_b + {0,1}, i_c + {0,1}).
  lo[b] -= 1;
  lo[c] -= 1;
  held.faces = grid::IndexBox{lo, hi};
}

void FaceNodeTransfer::increments_to_faces(
    MacGrid& mac, const NodeFields& u_star, const std::array<std::vector<double>, 3>& u_n,
    std::span<const std::uint8_t> node_valid_before,
    const std::array<std::vector<std::uint8_t>, 3>& face_swept, const ShellGeometry& shells,
    const geometry::ShellBand* band, const DomainBoundary& boundary, const CutFaces* cut) {
  for (int a = 0; a < 3; ++a) {
    mark_held_nodes(boundary, a);
    const HeldNodes& held = m_held[a];
    const Location loc = face_location(a);
    const int b = (a + 1) % 3;
    const int c = (a + 2) % 3;
    auto& u = mac.face_velocity(a);
    const auto& us = u_star.velocity(a);
    const auto& un = u_n[a];
    const std::span<const std::uint8_t> in_band =
        band ? band->flags(loc) : std::span<const std::uint8_t>();
    const bool has_swept = !face_swept[a].empty();
    const Eigen::Vector3i n = m_grid.counts(loc);
    const Eigen::Vector3i nodes = m_grid.counts(Location::Node);
    // Node offsets of the four corners (i_b + {0,1}, i_c + {0,1}) of a face of family a.
    const std::int64_t node_stride[3] = {1, nodes.x(), std::int64_t(nodes.x()) * nodes.y()};
    const std::int64_t corner_offset[4] = {0, node_stride[c], node_stride[b],
                                           node_stride[b] + node_stride[c]};
    // One face, any path: fixed faces kept, else the mean increment of its nodes (the
    // held source nodes and, near shells, the nodes it cannot see left out).
    const auto face_update = [&](int i, int j, int k) {
      const std::int64_t face = i + std::int64_t(n.x()) * (j + std::int64_t(n.y()) * k);
      const Eigen::Vector3i ijk(i, j, k);
      if (fixed_boundary_face(m_grid, boundary, a, ijk)) return;
      const std::int64_t first = i + std::int64_t(nodes.x()) * (j + std::int64_t(nodes.y()) * k);
      std::int64_t corner[4];
      for (int m = 0; m < 4; ++m) corner[m] = first + corner_offset[m];
      const bool rays = !in_band.empty() && in_band[face] != 0;
      const bool near_source = held.faces.contains(ijk);
      const auto held_node = [&](std::int64_t v) { return near_source && held.flag[v] != 0; };
      if (!rays) {
        double du = 0.0;
        int terms = 0;
        for (const std::int64_t v : corner)
          if (!held_node(v)) {
            du += us[v] - un[v];
            ++terms;
          }
        if (terms > 0) u[face] += du / terms;
        return;
      }
      const Eigen::Vector3d y = m_grid.position(loc, ijk);
      const bool swept = has_swept && face_swept[a][face] != 0;
      double du = 0.0;
      int du_terms = 0;
      double full = 0.0;
      int full_terms = 0;
      Eigen::Vector3d object_sum = Eigen::Vector3d::Zero();
      int object_terms = 0;
      for (const std::int64_t v : corner) {
        const Eigen::Vector3d x = m_grid.position(Location::Node, v);
        if (!shells.visible(y, x)) {
          object_sum += shells.object_velocity(y, x);
          ++object_terms;
          continue;
        }
        full += us[v];
        ++full_terms;
        if ((node_valid_before.empty() || node_valid_before[v] != 0) && !held_node(v)) {
          du += us[v] - un[v];
          ++du_terms;
        }
      }
      if (!swept && du_terms > 0) {
        u[face] += du / du_terms;
      } else if (full_terms > 0) {
        u[face] = full / full_terms;  // swept face, or only swept visible nodes
      } else if (object_terms > 0) {
        u[face] = object_sum[a] / object_terms;  // §4.2: no visible node
      }
    };
#pragma omp parallel for collapse(2) schedule(static)
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j) {
        const std::int64_t row = std::int64_t(n.x()) * (j + std::int64_t(n.y()) * k);
        // A row with no face in the shell band or next to a held source face, and no
        // fixed face but possibly its ends along x: the plain average of the four
        // increments, summed in face_update's order, over contiguous arrays.
        bool plain = !held.faces.contains(Eigen::Vector3i(held.faces.lo.x(), j, k));
        if (plain && !in_band.empty())
          plain = std::none_of(in_band.begin() + row, in_band.begin() + row + n.x(),
                               [](std::uint8_t f) { return f != 0; });
        if (plain && a != 0 && fixed_boundary_face(m_grid, boundary, a, Eigen::Vector3i(0, j, k)))
          continue;  // the whole row lies on a wall or inflow side
        if (!plain) {
          for (int i = 0; i < n.x(); ++i) face_update(i, j, k);
          continue;
        }
        int first = 0, last = n.x() - 1;
        if (a == 0) {  // the row's two ends lie on the x sides
          if (fixed_boundary_face(m_grid, boundary, 0, Eigen::Vector3i(0, j, k))) first = 1;
          if (fixed_boundary_face(m_grid, boundary, 0, Eigen::Vector3i(last, j, k))) --last;
        }
        const std::int64_t node0 = std::int64_t(nodes.x()) * (j + std::int64_t(nodes.y()) * k);
        const double* s0 = us.data() + node0 + corner_offset[0];
        const double* s1 = us.data() + node0 + corner_offset[1];
        const double* s2 = us.data() + node0 + corner_offset[2];
        const double* s3 = us.data() + node0 + corner_offset[3];
        const double* n0 = un.data() + node0 + corner_offset[0];
        const double* n1 = un.data() + node0 + corner_offset[1];
        const double* n2 = un.data() + node0 + corner_offset[2];
        const double* n3 = un.data() + node0 + corner_offset[3];
        double* out = u.data() + row;
        for (int i = first; i <= last; ++i)
          out[i] +=
              0.25 * ((((s0[i] - n0[i]) + (s1[i] - n1[i])) + (s2[i] - n2[i])) + (s3[i] - n3[i]));
      }
  }
  if (cut != nullptr)
    for (int a = 0; a < 3; ++a)
      increments_to_fragments(a, mac, u_star, u_n[a], node_valid_before, face_swept[a], *cut);
}

void FaceNodeTransfer::increments_to_fragments(int axis, MacGrid& mac, const NodeFields& u_star,
                                               const std::vector<double>& u_n,
                                               std::span<const std::uint8_t> node_valid_before,
                                               const std::vector<std::uint8_t>& face_swept,
                                               const CutFaces& cut) const {
  // Each fragment as a face: its own corners' mean increment (held source nodes and swept
  // ones left out), or their mean u* on a swept face; the MAC's face keeps the slots' one.
  const HeldNodes& held = m_held[axis];
  const Location loc = face_location(axis);
  const auto& us = u_star.velocity(axis);
  auto& u = mac.face_velocity(axis);
  auto& velocity = (*cut.velocities)[axis];
  const auto splits = cut.parts->split_faces(axis);
  const std::int64_t count = static_cast<std::int64_t>(splits.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < count; ++s) {
    const FaceSplit& split = splits[s];
    const Eigen::Vector3i ijk = m_grid.coordinates(loc, split.face);
    const bool swept = !face_swept.empty() && face_swept[split.face] != 0;
    const bool near_source = held.faces.contains(ijk);
    const auto fragments = cut.parts->fragments_of(axis, split);
    for (size_t k = 0; k < fragments.size(); ++k) {
      double du = 0.0, full = 0.0;
      int du_terms = 0, full_terms = 0;
      for (int corner = 0; corner < 4; ++corner) {
        if (!(fragments[k].corners >> corner & 1u)) continue;
        const std::int64_t v = m_grid.index(
            Location::Node, Eigen::Vector3i(ijk + CellParts::face_corner(axis, corner)));
        full += us[v];
        ++full_terms;
        if ((node_valid_before.empty() || node_valid_before[v] != 0) &&
            !(near_source && held.flag[v] != 0)) {
          du += us[v] - u_n[v];
          ++du_terms;
        }
      }
      double& value = velocity[split.first + k];
      if (!swept && du_terms > 0)
        value += du / du_terms;
      else if (full_terms > 0)
        value = full / full_terms;
      if (cut.parts->joins_slots(fragments[k])) u[split.face] = value;
    }
  }
}

}  // namespace shellflow::grid_fluid
