#include "multigrid_coarsening.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "cell_stencil.hpp"
#include "parallel_threshold.hpp"

namespace shellflow::linear::detail {
namespace {

using Level = MultigridPreconditioner::Level;
using SparseRows = MultigridPreconditioner::SparseRows;

/// A coupling of weight w between coarse unknowns a < b that is not a 7-point face.
struct Link {
  int a, b;
  float w;
};

/// One entry (fine unknown, coarse unknown, value) of a transfer correction.
struct Entry {
  int fine, coarse;
  float value;
};

/// A fine face of weight w as the coarsening of a §5.1 solve reads it
/// (Level::clamp_for_coarsening). A weak face (a heavy two-way sheet's β) counts as closed:
/// it splits coarse cells into parts as a closed shell does, so the coarse levels carry the
/// pressure jump across it. A strong one (a light sheet's β ≫ 1) counts as open, 1: the
/// rediscretised coarse face would sum its weight as if the whole coarse cell conducted
/// that well. The smoother keeps the true weights. On the two-way sheets of
/// MultigridShellSides this takes the iterations at 64³ from up to 2.8x those without the
/// sheet to at most 1.36x.
float coarsening_weight(float w) {
  constexpr float kWeakFace = 0.5f;
  return w < kWeakFace ? 0.0f : std::min(w, 1.0f);
}

/// A level read as a graph of unknowns: cells (structured faces, flat GridLaplacian
/// layout) and extra parts (links only).
struct LevelGraph {
  const Level& level;
  Eigen::Vector3i n;
  int cells;
  std::array<Eigen::Vector3i, 3> faces;

  explicit LevelGraph(const Level& l) : level(l), n(l.cells), cells(l.size()) {
    for (int a = 0; a < 3; ++a) {
      faces[a] = n;
      faces[a][a] += 1;
    }
  }
  int cell(const Eigen::Vector3i& c) const { return c.x() + n.x() * (c.y() + n.y() * c.z()); }
  Eigen::Vector3i coords(int cell) const {
    return {cell % n.x(), (cell / n.x()) % n.y(), cell / (n.x() * n.y())};
  }
  bool inside(const Eigen::Vector3i& c) const {
    return (c.array() >= 0).all() && (c.array() < n.array()).all();
  }
  /// Weight of face f of family a as the coarsening reads it (coarsening_weight).
  float face_at(int a, std::int64_t f) const {
    if (level.unit_weights) return float(level.open[a][f]);
    const float w = level.face_weight[a][f];
    return level.clamp_for_coarsening ? coarsening_weight(w) : w;
  }
  /// The same for the face of family a whose + cell is c (c[a] may equal n[a]: a domain face).
  float face(int a, const Eigen::Vector3i& c) const {
    return face_at(
        a, c.x() + std::int64_t(faces[a].x()) * (c.y() + std::int64_t(faces[a].y()) * c.z()));
  }
  bool active(int u) const { return level.inverse_diagonal[u] > 0.0f; }
  int cell_of(int u) const { return u < cells ? u : level.extra_cell[u - cells]; }
  /// Extras of cell c as unknowns [first, last).
  std::pair<int, int> extras_of(int c) const {
    if (level.extras == 0) return {0, 0};
    return {cells + level.cell_extra_start[c], cells + level.cell_extra_start[c + 1]};
  }
  float ground(int u) const {
    if (!level.ground.empty()) return level.ground[u];
    return level.dirichlet.empty() ? 0.0f : level.dirichlet[u];
  }
  /// Calls f(v, w) for each link of unknown u.
  template <class F>
  void for_links(int u, F&& f) const {
    if (!level.has_links()) return;
    for (int e = level.link_start[u]; e < level.link_start[u + 1]; ++e)
      f(level.link_to[e], level.link_weight[e]);
  }
};

/// Small union–find over a block's members (at most 8 cells and their extras).
struct UnionFind {
  std::vector<int> parent;
  void reset(int n) {
    parent.resize(n);
    for (int i = 0; i < n; ++i) parent[i] = i;
  }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

/// Per fine unknown: its part's number within its coarse cell (0: the largest part, which
/// keeps the cell's slot; -1: inactive). Per coarse cell: its number of parts.
void label_parts(const LevelGraph& g, const Eigen::Vector3i& nc, std::vector<int>& local,
                 std::vector<int>& parts, std::vector<std::uint8_t>& simple_cell) {
  local.resize(g.cells + g.level.extras);  // every entry written below
  parts.resize(nc.prod());
  simple_cell.resize(nc.prod());
  const bool go = nc.prod() >= kParallelThreshold / 8;
#pragma omp parallel if (go)
  {
    std::vector<int> members, size, label;
    UnionFind sets;
#pragma omp for collapse(2) schedule(static)
    for (int K = 0; K < nc.z(); ++K)
      for (int J = 0; J < nc.y(); ++J)
        for (int I = 0; I < nc.x(); ++I) {
          const Eigen::Vector3i lo(2 * I, 2 * J, 2 * K);
          const Eigen::Vector3i hi = (lo.array() + 1).min(g.n.array() - 1);
          const int block = I + nc.x() * (J + nc.y() * K);
          // The common case: every cell active, no extras, every inner face open: one part.
          members.clear();
          bool simple = true;
          for (int k = lo.z(); k <= hi.z(); ++k)
            for (int j = lo.y(); j <= hi.y(); ++j)
              for (int i = lo.x(); i <= hi.x(); ++i) {
                const Eigen::Vector3i c(i, j, k);
                const int cell = g.cell(c);
                local[cell] = -1;  // until labelled
                if (g.active(cell))
                  members.push_back(cell);
                else
                  simple = false;
                const auto [first, last] = g.extras_of(cell);
                for (int e = first; e < last; ++e) {
                  simple = false;
                  local[e] = -1;
                  if (g.active(e)) members.push_back(e);
                }
                for (int a = 0; a < 3; ++a)
                  if (c[a] == lo[a] && hi[a] > lo[a]) {
                    Eigen::Vector3i up = c;
                    up[a] += 1;
                    if (g.face(a, up) <= 0.0f) simple = false;
                  }
              }
          if (simple) {
            for (const int u : members) local[u] = 0;
            parts[block] = 1;
            simple_cell[block] = 1;
            continue;
          }
          const int m = static_cast<int>(members.size());
          const auto member_index = [&](int v) {
            for (int q = 0; q < m; ++q)
              if (members[q] == v) return q;
            return -1;
          };
          sets.reset(m);
          for (int q = 0; q < m; ++q) {
            const int u = members[q];
            if (u < g.cells) {
              const Eigen::Vector3i c = g.coords(u);
              for (int a = 0; a < 3; ++a)
                if (c[a] == lo[a] && hi[a] > lo[a]) {
                  Eigen::Vector3i up = c;
                  up[a] += 1;
                  if (g.face(a, up) > 0.0f) sets.join(q, member_index(g.cell(up)));
                }
            }
            g.for_links(u, [&](int v, float) {
              const int r = member_index(v);
              if (r >= 0) sets.join(q, r);
            });
          }
          // Number the parts: the largest 0 (it keeps the cell's slot), then by first member.
          size.assign(m, 0);
          for (int q = 0; q < m; ++q) ++size[sets.find(q)];
          int largest = -1;
          for (int q = 0; q < m; ++q)
            if (size[q] > 0 && (largest < 0 || size[q] > size[largest])) largest = q;
          label.assign(m, -1);
          int count = 0;
          if (largest >= 0) label[largest] = count++;
          for (int q = 0; q < m; ++q) {
            const int root = sets.find(q);
            if (label[root] < 0) label[root] = count++;
            local[members[q]] = label[root];
          }
          parts[block] = count;
          simple_cell[block] = 0;
        }
  }
}

/// Sparse rows from entries already sorted by (row key): key(e) picks the row.
template <class Key, class Column>
void rows_from(const std::vector<Entry>& entries, Key key, Column column, SparseRows& out) {
  out.clear();
  for (const Entry& e : entries) {
    if (out.row.empty() || out.row.back() != key(e)) {
      if (!out.row.empty()) out.start.push_back(static_cast<int>(out.column.size()));
      out.row.push_back(key(e));
    }
    out.column.push_back(column(e));
    out.value.push_back(e.value);
  }
  if (!out.row.empty()) out.start.push_back(static_cast<int>(out.column.size()));
}

}  // namespace

void compute_inverse_diagonal(Level& level) {
  const auto s = stencil_of(level.cells);
  level.inverse_diagonal.resize(level.unknowns());
  const float* x = level.inverse_diagonal.data();  // not read: the sum is ignored
  float* out = level.inverse_diagonal.data();
  const float* dirichlet = level.dirichlet.empty() ? nullptr : level.dirichlet.data();
  const bool go = level.size() >= kParallelThreshold;
  const auto cells = [&, out, dirichlet](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel for collapse(2) schedule(static) if (go)
    for (int k = 0; k < s.nz; ++k)
      for (int j = 0; j < s.ny; ++j)
        for_row(s, wx, wy, wz, x, j, k, 0, 1, [&](int, std::int64_t c, float d, float) {
          if (dirichlet != nullptr) d += dirichlet[c];
          out[c] = d > 0.0f ? 1.0f / d : 0.0f;  // isolated cell: left at 0
        });
  };
  with_weights(level, cells);
  for (int e = 0; e < level.extras; ++e) {
    const int u = level.size() + e;
    float d = level.ground[u];
    for (int l = level.link_start[u]; l < level.link_start[u + 1]; ++l) d += level.link_weight[l];
    out[u] = d > 0.0f ? 1.0f / d : 0.0f;
  }
}

void coarsen_level(Level& fine, Level& coarse) {
  const LevelGraph g(fine);
  const Eigen::Vector3i nc = coarse.cells;
  const int coarse_cells = nc.prod();

  // 1. Parts of each coarse cell and the coarse unknown of every fine one.
  // Scratch kept in the levels, so that a compute() per step reuses its memory.
  std::vector<int>& local = fine.scratch_part;
  std::vector<int>& parts = coarse.scratch_part;
  // Simple coarse cells: every fine cell active, its first part, no extras, inner faces open.
  std::vector<std::uint8_t>& simple = coarse.scratch_simple;
  label_parts(g, nc, local, parts, simple);
  std::vector<int>& extra_start = coarse.scratch_extra_start;
  extra_start.resize(coarse_cells + 1);
  extra_start[0] = 0;
  for (int c = 0; c < coarse_cells; ++c)
    extra_start[c + 1] = extra_start[c] + std::max(parts[c] - 1, 0);
  coarse.extras = extra_start[coarse_cells];
  coarse.extra_cell.resize(coarse.extras);
  for (int c = 0; c < coarse_cells; ++c)
    for (int e = extra_start[c]; e < extra_start[c + 1]; ++e) coarse.extra_cell[e] = c;
  if (coarse.extras > 0)
    coarse.cell_extra_start = extra_start;
  else
    coarse.cell_extra_start.clear();
  const int fine_unknowns = fine.unknowns();
  std::vector<int>& of = fine.coarse_part;
  of.resize(fine_unknowns);
  const auto coarse_unknown = [&](int part, int block) {
    return part < 0 ? -1 : part == 0 ? block : coarse_cells + extra_start[block] + part - 1;
  };
#pragma omp parallel for collapse(2) schedule(static) if (g.cells >= kParallelThreshold)
  for (int k = 0; k < g.n.z(); ++k)
    for (int j = 0; j < g.n.y(); ++j) {
      const int row = g.n.x() * (j + g.n.y() * k);
      const int block_row = nc.x() * (j / 2 + nc.y() * (k / 2));
      for (int i = 0; i < g.n.x(); ++i)
        of[row + i] = coarse_unknown(local[row + i], block_row + i / 2);
    }
  for (int e = 0; e < fine.extras; ++e) {
    const Eigen::Vector3i c = g.coords(fine.extra_cell[e]);
    const int block = c.x() / 2 + nc.x() * (c.y() / 2 + nc.y() * (c.z() / 2));
    of[g.cells + e] = coarse_unknown(local[g.cells + e], block);
  }

  // 2. Coarse operator, rediscretised per part: half the fine couplings joining two parts
  //    (a 7-point face where both are their cells' first parts, a link otherwise), half the
  //    members' conductances to p = 0. Each coarse cell writes its own low faces (and high
  //    domain faces) and its parts' ground, so the loop over cells needs no locks.
  const int coarse_unknowns = coarse_cells + coarse.extras;
  coarse.unit_weights = false;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3i faces = nc;
    faces[a] += 1;
    auto& w = coarse.weight[a];
    w.resize(faces.prod());
    std::fill(w.begin(), w.end(), 0.0f);
    coarse.face_weight[a] = w.data();
    coarse.open[a].clear();
  }
  coarse.clamp_for_coarsening = false;
  coarse.ground.assign(coarse_unknowns, 0.0f);
  std::vector<Link> links;
  const bool go = coarse_cells >= kParallelThreshold / 8;
  std::array<int, 3> face_x{}, face_y{};  // face counts along x and y of each family
  for (int a = 0; a < 3; ++a) {
    face_x[a] = g.faces[a].x();
    face_y[a] = g.faces[a].y();
  }
  const std::array<int, 3> cell_stride{1, g.n.x(), g.n.x() * g.n.y()};
  const std::array<int, 3> coarse_stride{1, nc.x(), nc.x() * nc.y()};
  const bool members_matter =
      !fine.dirichlet.empty() || !fine.ground.empty() || fine.has_links() || fine.extras > 0;
#pragma omp parallel if (go)
  {
    std::vector<Link> mine;
#pragma omp for collapse(2) schedule(static)
    for (int K = 0; K < nc.z(); ++K)
      for (int J = 0; J < nc.y(); ++J)
        for (int I = 0; I < nc.x(); ++I) {
          const Eigen::Vector3i B(I, J, K);
          const int block = I + nc.x() * (J + nc.y() * K);
          const Eigen::Vector3i lo = 2 * B;
          const Eigen::Vector3i hi = (lo.array() + 1).min(g.n.array() - 1);
          const auto coarse_face = [&](int a, const Eigen::Vector3i& C) -> float& {
            Eigen::Vector3i faces = nc;
            faces[a] += 1;
            return coarse.weight[a][C.x() + std::int64_t(faces.x()) *
                                                (C.y() + std::int64_t(faces.y()) * C.z())];
          };
          // Between parts cu (in B - e_a) and cv (in B), or cv and the domain (cu < 0).
          const auto couple = [&](int a, int cu, int cv, float w, bool domain) {
            if (domain) {
              if (cv == block)
                coarse_face(a, B) += 0.5f * w;
              else
                coarse.ground[cv] += 0.5f * w;
              return;
            }
            Eigen::Vector3i below = B;
            below[a] -= 1;
            if (cv == block && cu == below.x() + nc.x() * (below.y() + nc.y() * below.z()))
              coarse_face(a, B) += 0.5f * w;
            else
              mine.push_back({std::min(cu, cv), std::max(cu, cv), 0.5f * w});
          };
          for (int a = 0; a < 3; ++a) {
            // Fine faces on B's low face along a (their + cells lie in B), then on its high
            // face where that is the domain's. Plain index arithmetic: the hot loop of compute().
            const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
            const int below = B[a] == 0 ? -1 : block - coarse_stride[a];
            if (simple[block] != 0 && (below < 0 || simple[below] != 0)) {
              // Both cells whole (or the domain beyond): the plain face sum of McAdams et al.
              for (const bool high : {false, true}) {
                if (high && B[a] != nc[a] - 1) break;
                int f[3];
                f[a] = high ? g.n[a] : lo[a];
                float sum = 0.0f;
                for (int p = lo[b1]; p <= hi[b1]; ++p)
                  for (int q = lo[b2]; q <= hi[b2]; ++q) {
                    f[b1] = p;
                    f[b2] = q;
                    const std::int64_t face =
                        f[0] + std::int64_t(face_x[a]) * (f[1] + std::int64_t(face_y[a]) * f[2]);
                    sum += g.face_at(a, face);
                  }
                Eigen::Vector3i C = B;
                if (high) C[a] += 1;
                coarse_face(a, C) += 0.5f * sum;
              }
              continue;
            }
            for (const bool high : {false, true}) {
              if (high && B[a] != nc[a] - 1) break;
              float plain = 0.0f;  // couplings between the two cells' first parts
              int v[3];
              v[a] = high ? g.n[a] - 1 : lo[a];
              for (int p = lo[b1]; p <= hi[b1]; ++p)
                for (int q = lo[b2]; q <= hi[b2]; ++q) {
                  v[b1] = p;
                  v[b2] = q;
                  int f[3] = {v[0], v[1], v[2]};
                  if (high) f[a] += 1;
                  const std::int64_t face =
                      f[0] + std::int64_t(face_x[a]) * (f[1] + std::int64_t(face_y[a]) * f[2]);
                  const float w = g.face_at(a, face);
                  if (w <= 0.0f) continue;
                  const int cell = v[0] + g.n.x() * (v[1] + g.n.y() * v[2]);
                  const int cv = of[cell];
                  if (high || below < 0) {  // a domain face
                    if (cv == block)
                      plain += w;
                    else
                      coarse.ground[cv] += 0.5f * w;
                  } else {
                    const int cu = of[cell - cell_stride[a]];
                    if (cv == block && cu == below)
                      plain += w;
                    else
                      mine.push_back({std::min(cu, cv), std::max(cu, cv), 0.5f * w});
                  }
                }
              if (plain != 0.0f) {
                Eigen::Vector3i C = B;
                if (high) C[a] += 1;
                coarse_face(a, C) += 0.5f * plain;
              }
            }
          }
          // Members: links to parts of lower neighbours, and conductances to p = 0 (nothing
          // to do on a smoke grid without extras: the common fine level).
          if (!members_matter) continue;
          for (int k = lo.z(); k <= hi.z(); ++k)
            for (int j = lo.y(); j <= hi.y(); ++j)
              for (int i = lo.x(); i <= hi.x(); ++i) {
                const int cell = g.cell({i, j, k});
                const auto [first, last] = g.extras_of(cell);
                for (int e = first - 1; e < last; ++e) {
                  const int u = e < first ? cell : e;  // the cell, then its extras
                  if (of[u] < 0) continue;
                  coarse.ground[of[u]] += 0.5f * g.ground(u);
                  g.for_links(u, [&](int v, float w) {
                    const Eigen::Vector3i d = g.coords(g.cell_of(v)) / 2 - B;
                    for (int a = 0; a < 3; ++a)
                      if (d[a] == -1 && d.cwiseAbs().sum() == 1) couple(a, of[v], of[u], w, false);
                  });
                }
              }
        }
#pragma omp critical
    links.insert(links.end(), mine.begin(), mine.end());
  }
  // Links: merge duplicates, then both directions as CSR rows.
  std::sort(links.begin(), links.end(),
            [](const Link& p, const Link& q) {  // w too: the same sums in every run
              return p.a != q.a ? p.a < q.a : p.b != q.b ? p.b < q.b : p.w < q.w;
            });
  std::vector<Link> merged;
  for (const Link& l : links) {
    if (!merged.empty() && merged.back().a == l.a && merged.back().b == l.b)
      merged.back().w += l.w;
    else
      merged.push_back(l);
  }
  coarse.link_start.clear();
  coarse.link_to.clear();
  coarse.link_weight.clear();
  coarse.row_has_links.clear();
  // Rows exist whenever there are extras (an extra part may have no links at all: a part
  // reaching only an open domain face, or one enclosed inside its cell).
  if (!merged.empty() || coarse.extras > 0) {
    coarse.link_start.assign(coarse_unknowns + 1, 0);
    for (const Link& l : merged) {
      ++coarse.link_start[l.a + 1];
      ++coarse.link_start[l.b + 1];
    }
    for (int u = 0; u < coarse_unknowns; ++u) coarse.link_start[u + 1] += coarse.link_start[u];
    coarse.link_to.resize(2 * merged.size());
    coarse.link_weight.resize(2 * merged.size());
    std::vector<int> next(coarse.link_start.begin(), coarse.link_start.end() - 1);
    for (const Link& l : merged) {
      coarse.link_to[next[l.a]] = l.b;
      coarse.link_weight[next[l.a]++] = l.w;
      coarse.link_to[next[l.b]] = l.a;
      coarse.link_weight[next[l.b]++] = l.w;
    }
    coarse.row_has_links.assign(std::int64_t(nc.y()) * nc.z(), 0);  // read only with links
    for (int c = 0; c < coarse_cells; ++c)
      if (coarse.link_start[c + 1] > coarse.link_start[c]) coarse.row_has_links[c / nc.x()] = 1;
  }
  // A cell's diagonal beyond its faces: ground plus links (empty when zero everywhere).
  bool any = false;
  coarse.dirichlet.assign(coarse_cells, 0.0f);
  for (int c = 0; c < coarse_cells; ++c) {
    float d = coarse.ground[c];
    if (coarse.has_links())
      for (int l = coarse.link_start[c]; l < coarse.link_start[c + 1]; ++l)
        d += coarse.link_weight[l];
    coarse.dirichlet[c] = d;
    any = any || d != 0.0f;
  }
  if (!any) coarse.dirichlet.clear();
  compute_inverse_diagonal(coarse);

  // 3. Transfers. Plain trilinear P on cells; a fine unknown whose eight corners are not all
  //    reached through open faces inside its stencil (or not the cells' first parts) gets
  //    its own row, stored as the difference from the plain one.
  const int threads = omp_get_max_threads();
  std::vector<std::vector<Entry>> per_thread(threads);
  const bool go_fine = fine.size() >= kParallelThreshold;
#pragma omp parallel if (go_fine)
  {
    std::vector<Entry>& mine = per_thread[omp_get_thread_num()];
    mine.clear();
    std::vector<int> reached, corner, queue;
    const auto row_of = [&](int u) {
      const Eigen::Vector3i c = g.coords(g.cell_of(u));
      std::array<Parents, 3> p;
      std::array<int, 3> side;
      int far_axes = 0;
      for (int a = 0; a < 3; ++a) {
        p[a] = parents_of(c[a], nc[a]);
        side[a] = (c[a] % 2 == 1) ? 1 : -1;
        if (p[a].second_weight > 0.0f) far_axes |= 1 << a;
      }
      const auto corner_cell = [&](int S) {
        Eigen::Vector3i w = c;
        for (int a = 0; a < 3; ++a)
          if (S >> a & 1) w[a] += side[a];
        return w;
      };
      const auto tensor_weight = [&](int S) {
        double w = 1.0;
        for (int a = 0; a < 3; ++a) w *= (S >> a & 1) ? p[a].second_weight : p[a].first_weight;
        return w;
      };
      // Standard row (cells only): the eight parents' first parts.
      std::array<std::pair<int, double>, 16> standard{};
      int standard_count = 0;
      if (u < g.cells)
        for (int S = 0; S < 8; ++S)
          if ((S & ~far_axes) == 0) {
            const Eigen::Vector3i w = corner_cell(S);
            standard[standard_count++] = {w.x() / 2 + nc.x() * (w.y() / 2 + nc.y() * (w.z() / 2)),
                                          tensor_weight(S)};
          }
      // Unknowns reached from u through open faces and links inside the stencil's cells.
      const auto corner_of_cell = [&](const Eigen::Vector3i& w) {
        int S = 0;
        for (int a = 0; a < 3; ++a) {
          const int d = w[a] - c[a];
          if (d == 0) continue;
          if (d != side[a] || !(far_axes >> a & 1)) return -1;
          S |= 1 << a;
        }
        return S;
      };
      reached.assign(1, u);
      corner.assign(1, 0);
      for (size_t q = 0; q < reached.size(); ++q) {
        const int v = reached[q];
        const int S = corner[q];
        const auto visit = [&](int t, int St) {
          if (St < 0 || of[t] < 0) return;
          if (std::find(reached.begin(), reached.end(), t) != reached.end()) return;
          reached.push_back(t);
          corner.push_back(St);
        };
        if (v < g.cells) {
          const Eigen::Vector3i cv = g.coords(v);
          for (int a = 0; a < 3; ++a) {
            if (!(far_axes >> a & 1)) continue;
            const int step = (S >> a & 1) ? -side[a] : side[a];
            Eigen::Vector3i t = cv;
            t[a] += step;
            Eigen::Vector3i f = step > 0 ? t : cv;
            if (g.face(a, f) > 0.0f) visit(g.cell(t), S ^ (1 << a));
          }
        }
        g.for_links(v, [&](int t, float) { visit(t, corner_of_cell(g.coords(g.cell_of(t)))); });
      }
      // Weights: tensor weights per corner; an unreached corner passes its weight to the
      // reached corners with the most far axes among its subsets (its nearest), in equal
      // shares; a corner holding several reached parts splits its weight between them.
      std::array<double, 8> W{};
      std::array<int, 8> parts_at{};
      for (int S = 0; S < 8; ++S) W[S] = (S & ~far_axes) == 0 ? tensor_weight(S) : 0.0;
      std::array<std::array<int, 8>, 8> part_list{};
      for (size_t q = 0; q < reached.size(); ++q) {
        const int S = corner[q];
        const int part = of[reached[q]];
        bool seen = false;
        for (int t = 0; t < parts_at[S]; ++t) seen = seen || part_list[S][t] == part;
        if (!seen && parts_at[S] < 8) part_list[S][parts_at[S]++] = part;
      }
      for (int bits = 3; bits >= 1; --bits)
        for (int S = 0; S < 8; ++S) {
          if (__builtin_popcount(S) != bits || (S & ~far_axes) != 0 || parts_at[S] > 0) continue;
          int best = -1, count = 0;
          for (int T = 0; T < 8; ++T) {
            if ((T & ~S) != 0 || T == S || parts_at[T] == 0) continue;
            const int pc = __builtin_popcount(T);
            if (pc > best) best = pc, count = 0;
            if (pc == best) ++count;
          }
          for (int T = 0; T < 8; ++T)
            if ((T & ~S) == 0 && T != S && parts_at[T] > 0 && __builtin_popcount(T) == best)
              W[T] += W[S] / count;
          W[S] = 0.0;
        }
      // Row minus the standard one.
      std::array<std::pair<int, double>, 32> delta{};
      int count = 0;
      const auto add = [&](int col, double value) {
        for (int t = 0; t < count; ++t)
          if (delta[t].first == col) {
            delta[t].second += value;
            return;
          }
        if (count < 32) delta[count++] = {col, value};
      };
      for (int S = 0; S < 8; ++S)
        for (int t = 0; t < parts_at[S]; ++t) add(part_list[S][t], W[S] / parts_at[S]);
      for (int t = 0; t < standard_count; ++t) add(standard[t].first, -standard[t].second);
      for (int t = 0; t < count; ++t)
        if (std::abs(delta[t].second) > 1e-9)
          mine.push_back({u, delta[t].first, static_cast<float>(delta[t].second)});
    };
    // The stencil of a fine cell along an axis is the pair {2D - 1, 2D} that holds it (its
    // far parent lies on its partner's side), so the eight cells of a "dual" block D share
    // one stencil. A dual block whose cells are all their coarse cells' first parts, with
    // no extras and every inner face open, keeps the plain trilinear rows; only the others
    // (near shells, air, walls inside the domain) compute their own.
    const Eigen::Vector3i dual = g.n / 2 + Eigen::Vector3i::Ones();
#pragma omp for collapse(2) schedule(static)
    for (int DK = 0; DK < dual.z(); ++DK)
      for (int DJ = 0; DJ < dual.y(); ++DJ)
        for (int DI = 0; DI < dual.x(); ++DI) {
          const Eigen::Vector3i D(DI, DJ, DK);
          const Eigen::Vector3i lo = (2 * D.array() - 1).max(0);
          const Eigen::Vector3i hi = (2 * D).cwiseMin(g.n - Eigen::Vector3i::Ones());
          bool plain = true;
          for (int k = lo.z(); k <= hi.z() && plain; ++k)
            for (int j = lo.y(); j <= hi.y() && plain; ++j)
              for (int i = lo.x(); i <= hi.x() && plain; ++i) {
                const int cell = g.cell({i, j, k});
                if (of[cell] != i / 2 + nc.x() * (j / 2 + nc.y() * (k / 2))) plain = false;
                const auto [first, last] = g.extras_of(cell);
                if (first != last) plain = false;
                if (i < hi.x() && g.face(0, {i + 1, j, k}) <= 0.0f) plain = false;
                if (j < hi.y() && g.face(1, {i, j + 1, k}) <= 0.0f) plain = false;
                if (k < hi.z() && g.face(2, {i, j, k + 1}) <= 0.0f) plain = false;
              }
          if (plain) continue;
          for (int k = lo.z(); k <= hi.z(); ++k)
            for (int j = lo.y(); j <= hi.y(); ++j)
              for (int i = lo.x(); i <= hi.x(); ++i) {
                const int u = g.cell({i, j, k});
                if (of[u] >= 0) row_of(u);
              }
        }
#pragma omp single
    {
      for (int e = 0; e < fine.extras; ++e)
        if (of[g.cells + e] >= 0) row_of(g.cells + e);
    }
  }
  // Prolongation rows by fine unknown (entries exist near shells only, so sorting is cheap;
  // stable, so each row keeps its order in every run).
  std::vector<Entry> entries;
  for (const auto& t : per_thread) entries.insert(entries.end(), t.begin(), t.end());
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& p, const Entry& q) { return p.fine < q.fine; });
  rows_from(
      entries, [](const Entry& e) { return e.fine; }, [](const Entry& e) { return e.coarse; },
      fine.prolongation_correction);
  // Restriction rows by coarse unknown (the transpose).
  std::vector<Entry> by_coarse = entries;
  std::stable_sort(by_coarse.begin(), by_coarse.end(),
                   [](const Entry& p, const Entry& q) { return p.coarse < q.coarse; });
  rows_from(
      by_coarse, [](const Entry& e) { return e.coarse; }, [](const Entry& e) { return e.fine; },
      fine.restriction_correction);
}

namespace {

/// flag[i] = 1 for the active cells of row (j, k) with an interior face f that
/// `selected(w_f)` picks towards an active neighbour; other entries are left alone.
template <class W, class Select>
void flag_faces_to_active(const Level& level, const CellStencil& s, const W* wx, const W* wy,
                          const W* wz, int j, int k, Select selected, std::uint8_t* flag) {
  const std::int64_t row = s.cell_row(j, k);
  const float* active = level.inverse_diagonal.data() + row;  // > 0: active
  const W* fx = wx + s.face_x_row(j, k);
  const W* fy_lo = wy + s.face_y_row(j, k);
  const W* fy_hi = fy_lo + s.nx;
  const W* fz_lo = wz + s.face_z_row(j, k);
  const W* fz_hi = fz_lo + s.plane();
  const float* down = j > 0 ? active - s.nx : nullptr;
  const float* up = j + 1 < s.ny ? active + s.nx : nullptr;
  const float* back = k > 0 ? active - s.plane() : nullptr;
  const float* front = k + 1 < s.nz ? active + s.plane() : nullptr;
  for (int i = 0; i < s.nx; ++i)
    if (active[i] > 0.0f &&  // the selected faces are rare: test them first
        ((selected(fx[i]) && i > 0 && active[i - 1] > 0.0f) ||
         (selected(fx[i + 1]) && i + 1 < s.nx && active[i + 1] > 0.0f) ||
         (selected(fy_lo[i]) && down != nullptr && down[i] > 0.0f) ||
         (selected(fy_hi[i]) && up != nullptr && up[i] > 0.0f) ||
         (selected(fz_lo[i]) && back != nullptr && back[i] > 0.0f) ||
         (selected(fz_hi[i]) && front != nullptr && front[i] > 0.0f)))
      flag[i] = 1;
}

}  // namespace

std::vector<std::uint8_t> fractional_face_cells(const Level& level) {
  const auto s = stencil_of(level.cells);
  if (level.unit_weights) return {};  // every face 0 or 1
  std::vector<std::uint8_t> out(level.size(), 0);
  const auto fractional = [](float w) { return w != 0.0f && w != 1.0f; };
#pragma omp parallel for collapse(2) schedule(static) if (level.size() >= kParallelThreshold)
  for (int k = 0; k < s.nz; ++k)
    for (int j = 0; j < s.ny; ++j)
      flag_faces_to_active(level, s, level.face_weight[0], level.face_weight[1],
                           level.face_weight[2], j, k, fractional, out.data() + s.cell_row(j, k));
  return out;
}

std::vector<std::uint8_t> coarsen_flags(const std::vector<std::uint8_t>& fine,
                                        const Eigen::Vector3i& fine_cells,
                                        const Eigen::Vector3i& coarse_cells) {
  std::vector<std::uint8_t> out(coarse_cells.prod(), 0);
  const auto fs = stencil_of(fine_cells), cs = stencil_of(coarse_cells);
#pragma omp parallel for collapse(2) schedule(static) if (fine.size() >= kParallelThreshold)
  for (int K = 0; K < cs.nz; ++K)
    for (int J = 0; J < cs.ny; ++J) {
      std::uint8_t* to = out.data() + cs.cell_row(J, K);
      for (int k = 2 * K; k < std::min(2 * K + 2, fs.nz); ++k)
        for (int j = 2 * J; j < std::min(2 * J + 2, fs.ny); ++j) {
          const std::uint8_t* row = fine.data() + fs.cell_row(j, k);
          for (int i = 0; i < fs.nx; ++i) to[i / 2] |= row[i];
        }
    }
  return out;
}

void find_near_shell(Level& level, int reach, const std::vector<std::uint8_t>& carried) {
  const auto s = stencil_of(level.cells);
  const int rows = s.ny * s.nz;
  const bool go = level.size() >= kParallelThreshold;
  // 1. Seeds, and which rows hold one; each seeded row then dilated along x (box distance).
  std::vector<std::uint8_t> along_x(level.size()), row_seeded(rows);
  bool any = false;
  const int* extra_start = level.extras > 0 ? level.cell_extra_start.data() : nullptr;
  const auto closed = [](auto w) { return w == 0; };
  with_weights(level, [&](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel if (go)
    {
      std::vector<std::uint8_t> seed(s.nx);  // this row's seeds
#pragma omp for collapse(2) schedule(static) reduction(|| : any)
      for (int k = 0; k < s.nz; ++k)
        for (int j = 0; j < s.ny; ++j) {
          const std::int64_t row = s.cell_row(j, k);
          // A cell with extra parts, a carried one, or one closed off from an active
          // neighbour.
          for (int i = 0; i < s.nx; ++i)
            seed[i] = (extra_start != nullptr && extra_start[row + i + 1] > extra_start[row + i]) ||
                      (!carried.empty() && carried[row + i] != 0);
          flag_faces_to_active(level, s, wx, wy, wz, j, k, closed, seed.data());
          const bool seeded = std::find(seed.begin(), seed.end(), 1) != seed.end();
          row_seeded[j + s.ny * k] = seeded ? 1 : 0;
          if (!seeded) continue;
          any = true;
          for (int i = 0; i < s.nx; ++i) {
            std::uint8_t v = 0;
            for (int d = std::max(i - reach, 0); d <= std::min(i + reach, s.nx - 1) && !v; ++d)
              v = seed[d];
            along_x[row + i] = v;
          }
        }
    }
  });
  level.near_shell.clear();
  if (!any) return;
  // 2. Per row, the union of the seeded rows within reach in y and z, as runs of cells
  //    (each thread's rows are one contiguous run of rows, so the threads' lists
  //    concatenate in flat order).
  const int threads = go ? omp_get_max_threads() : 1;
  std::vector<std::vector<Level::NearRun>> found(threads);
#pragma omp parallel num_threads(threads) if (go)
  {
    auto& mine = found[omp_get_thread_num()];
    std::vector<std::uint8_t> near(s.nx);
#pragma omp for collapse(2) schedule(static)
    for (int k = 0; k < s.nz; ++k)
      for (int j = 0; j < s.ny; ++j) {
        bool touched = false;
        for (int kk = std::max(k - reach, 0); kk <= std::min(k + reach, s.nz - 1); ++kk)
          for (int jj = std::max(j - reach, 0); jj <= std::min(j + reach, s.ny - 1); ++jj) {
            if (row_seeded[jj + s.ny * kk] == 0) continue;
            const std::uint8_t* source = along_x.data() + s.cell_row(jj, kk);
            if (!touched)
              std::copy(source, source + s.nx, near.begin());
            else
              for (int i = 0; i < s.nx; ++i) near[i] |= source[i];
            touched = true;
          }
        if (!touched) continue;
        for (int i = 0; i < s.nx;) {
          if (near[i] == 0) {
            ++i;
            continue;
          }
          const int first = i;
          while (i < s.nx && near[i] != 0) ++i;
          mine.push_back({j, k, first, i});
        }
      }
  }
  for (const auto& runs : found)
    level.near_shell.insert(level.near_shell.end(), runs.begin(), runs.end());
}

}  // namespace shellflow::linear::detail
