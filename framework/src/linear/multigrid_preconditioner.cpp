#include "shellflow/linear/multigrid_preconditioner.hpp"

#include <omp.h>

#include <algorithm>
#include <string>

#include "cell_stencil.hpp"
#include "multigrid_coarsening.hpp"
#include "parallel_threshold.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {
namespace {

using detail::kParallelThreshold;
using Level = MultigridPreconditioner::Level;
using detail::Parents;
using detail::parents_of;
using detail::with_weights;

// Coarsen while every axis has at least this many cells (coarsest: 4–7 on the shortest).
constexpr int kMinCellsToCoarsen = 8;

/// Children of coarse cell I along one axis with their restriction weights: exactly the
/// transpose of parents_of (so that R = P^T and the V-cycle stays symmetric).
struct Children {
  int count = 0;
  int fine[4];
  float weight[4];
};

std::vector<Children> children_along(int fine_cells, int coarse_cells) {
  std::vector<Children> out(coarse_cells);
  for (int f = 0; f < fine_cells; ++f) {
    const Parents p = parents_of(f, coarse_cells);
    for (const auto& [coarse, w] :
         {std::pair{p.first, p.first_weight}, std::pair{p.second, p.second_weight}}) {
      if (w == 0.0f) continue;
      auto& c = out[coarse];
      c.fine[c.count] = f;
      c.weight[c.count] = w;
      ++c.count;
    }
  }
  return out;
}

bool parallel(const Level& level) {
  return level.cells.prod() >= kParallelThreshold;
}

/// Σ w x_v over the links of unknown u (its couplings that involve an extra part).
inline float link_sum(const Level& level, std::int64_t u, const float* x) {
  float sum = 0.0f;
  for (int l = level.link_start[u]; l < level.link_start[u + 1]; ++l)
    sum += level.link_weight[l] * x[level.link_to[l]];
  return sum;
}

/// Red (0) or black (1): a part takes its cell's colour. Parts couple only to parts of face
/// neighbours (never within their cell), so red–black ordering still decouples each colour.
int colour_of_cell(const Level& level, int cell) {
  const int nx = level.cells.x(), ny = level.cells.y();
  return (cell % nx + (cell / nx) % ny + cell / (nx * ny)) & 1;
}

/// Calls f(u) for every extra unknown u of colour `colour` (of both for colour < 0).
template <class F>
void for_extras(const Level& level, int colour, F&& f) {
  const int cells = level.size();
#pragma omp parallel for schedule(static) if (level.extras >= kParallelThreshold)
  for (int e = 0; e < level.extras; ++e)
    if (colour < 0 || colour_of_cell(level, level.extra_cell[e]) == colour) f(cells + e);
}

/// The cells of colour `color` on row (j, k) of a level without extra parts:
/// x_u = (b_u + Σ w x_nb) / A_uu, or x_u = b_u / A_uu when `from_zero` (x = 0 elsewhere).
template <class W>
void sweep_row(const detail::CellStencil& s, const W* wx, const W* wy, const W* wz, float* x,
               const float* b, const float* inverse, int j, int k, int color, bool from_zero,
               float* sum, const float* zeros) {
  const std::int64_t row = s.cell_row(j, k);
  const int first = (j + k + color) & 1;
  if (from_zero) {
    for (int i = first; i < s.nx; i += 2) x[row + i] = b[row + i] * inverse[row + i];
    return;
  }
  detail::row_sums(s, wx, wy, wz, static_cast<const float*>(x), zeros, j, k, sum,
                   static_cast<float*>(nullptr));
  for (int i = first; i < s.nx; i += 2) x[row + i] = (b[row + i] + sum[i]) * inverse[row + i];
}

/// One red (color 0) or black (color 1) Gauss–Seidel half sweep: x_u = (b_u + Σ w x_nb) / A_uu
/// on the unknowns of that colour; unknowns of one colour only read the other's.
void half_sweep(const Level& level, int color) {
  const auto s = detail::stencil_of(level.cells);
  float* x = level.x;
  const float* b = level.b;
  const float* inverse = level.inverse_diagonal.data();
  const bool links = level.has_links();
  with_weights(level, [&](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel if (parallel(level))
    {
      // Whole rows in a vectorised pass into `sum`, then only this colour written back:
      // its neighbours are all of the other colour, which this half sweep leaves alone.
      std::vector<float> sum(s.nx), zeros(s.nx, 0.0f);
#pragma omp for collapse(2) schedule(static)
      for (int k = 0; k < s.nz; ++k)
        for (int j = 0; j < s.ny; ++j) {
          if (!links || level.row_has_links[j + std::int64_t(s.ny) * k] == 0) {
            sweep_row(s, wx, wy, wz, x, b, inverse, j, k, color, false, sum.data(), zeros.data());
            continue;
          }
          detail::row_sums(s, wx, wy, wz, static_cast<const float*>(x), zeros.data(), j, k,
                           sum.data(), static_cast<float*>(nullptr));
          const std::int64_t row = s.cell_row(j, k);
          for (int i = (j + k + color) & 1; i < s.nx; i += 2)
            x[row + i] = (b[row + i] + sum[i] + link_sum(level, row + i, x)) * inverse[row + i];
        }
    }
  });
  for_extras(level, color, [&](int u) { x[u] = (b[u] + link_sum(level, u, x)) * inverse[u]; });
}

/// The half sweep of colour `first` and then the other one's on a level without extra
/// parts, in one pass over the planes: each thread takes a slab of planes and sweeps the
/// other colour on plane k − 1 right after the first colour on plane k (it reads only
/// first-colour cells of planes k − 2 … k, all updated by then), while those planes are
/// still in cache; the slab's two end planes wait for the neighbouring slabs (a barrier).
/// Bit for bit the two half sweeps, with about half their memory traffic.
void fused_sweep(const Level& level, int first, bool from_zero) {
  const auto s = detail::stencil_of(level.cells);
  float* x = level.x;
  const float* b = level.b;
  const float* inverse = level.inverse_diagonal.data();
  const int second = 1 - first;
  with_weights(level, [&](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel if (parallel(level))
    {
      const int threads = omp_get_num_threads(), t = omp_get_thread_num();
      const int k0 = static_cast<int>(std::int64_t(s.nz) * t / threads);
      const int k1 = static_cast<int>(std::int64_t(s.nz) * (t + 1) / threads);
      std::vector<float> sum(s.nx), zeros(s.nx, 0.0f);
      const auto plane = [&](int k, int color, bool zero) {
        for (int j = 0; j < s.ny; ++j)
          sweep_row(s, wx, wy, wz, x, b, inverse, j, k, color, zero, sum.data(), zeros.data());
      };
      for (int k = k0; k < k1; ++k) {
        plane(k, first, from_zero);
        if (k - 1 > k0) plane(k - 1, second, false);
      }
#pragma omp barrier
      if (k1 > k0) plane(k0, second, false);
      if (k1 - 1 > k0) plane(k1 - 1, second, false);
    }
  });
}

/// Gauss–Seidel over the unknowns near a shell, in flat order (each cell, then its extra
/// parts) forward, or in exactly the reverse order backward (the adjoint of the forward
/// sweep, for the symmetric V-cycle).
void near_shell_sweep(const Level& level, bool forward) {
  const int runs = static_cast<int>(level.near_shell.size());
  if (runs == 0) return;
  const auto s = detail::stencil_of(level.cells);
  const int cells = level.size();
  float* x = level.x;
  const float* b = level.b;
  const float* inverse = level.inverse_diagonal.data();
  const bool links = level.has_links();
  const auto extras = [&](int cell, bool ascending) {
    if (level.extras == 0) return;
    const int first = cells + level.cell_extra_start[cell];
    const int last = cells + level.cell_extra_start[cell + 1];
    for (int t = 0; t < last - first; ++t) {
      const int u = ascending ? first + t : last - 1 - t;
      if (inverse[u] > 0.0f) x[u] = (b[u] + link_sum(level, u, x)) * inverse[u];
    }
  };
  with_weights(level, [&](const auto* wx, const auto* wy, const auto* wz) {
    for (int r = 0; r < runs; ++r) {
      const auto& run = level.near_shell[forward ? r : runs - 1 - r];
      const int j = run.j, k = run.k;
      const std::int64_t row = s.cell_row(j, k);
      const auto* fx = wx + s.face_x_row(j, k);
      const auto* fy = wy + s.face_y_row(j, k);
      const auto* fz = wz + s.face_z_row(j, k);
      const bool down = j > 0, up = j + 1 < s.ny, back = k > 0, front = k + 1 < s.nz;
      for (int t = 0; t < run.last - run.first; ++t) {
        const int i = forward ? run.first + t : run.last - 1 - t;
        const int u = static_cast<int>(row + i);
        if (!forward) extras(u, false);
        if (!(inverse[u] > 0.0f)) {
          if (forward) extras(u, true);
          continue;
        }
        float sum = links ? link_sum(level, u, x) : 0.0f;
        if (i > 0) sum += float(fx[i]) * x[u - 1];
        if (i + 1 < s.nx) sum += float(fx[i + 1]) * x[u + 1];
        if (down) sum += float(fy[i]) * x[u - s.nx];
        if (up) sum += float(fy[i + s.nx]) * x[u + s.nx];
        if (back) sum += float(fz[i]) * x[u - s.plane()];
        if (front) sum += float(fz[i + s.plane()]) * x[u + s.plane()];
        x[u] = (b[u] + sum) * inverse[u];
        if (forward) extras(u, true);
      }
    }
  });
}

/// The red half sweep from x = 0: x_u = b_u / A_uu on the red unknowns (black ones untouched).
void first_red_sweep(const Level& level) {
  const auto s = detail::stencil_of(level.cells);
  float* x = level.x;
  const float* b = level.b;
  const float* inverse = level.inverse_diagonal.data();
  with_weights(level, [&](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel for collapse(2) schedule(static) if (parallel(level))
    for (int k = 0; k < s.nz; ++k)
      for (int j = 0; j < s.ny; ++j)
        sweep_row(s, wx, wy, wz, x, b, inverse, j, k, 0, true, nullptr, nullptr);
  });
  for_extras(level, 0, [&](int u) { x[u] = b[u] * inverse[u]; });
}

/// r = b − A x on a level.
void level_residual(const Level& level) {
  const auto s = detail::stencil_of(level.cells);
  const float* x = level.x;
  const float* b = level.b;
  float* r = level.r;
  const float* dirichlet = level.dirichlet.empty() ? nullptr : level.dirichlet.data();
  const bool links = level.has_links();
  with_weights(level, [&](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel if (parallel(level))
    {
      std::vector<float> sum(s.nx), diagonal(s.nx), zeros(s.nx, 0.0f);
#pragma omp for collapse(2) schedule(static)
      for (int k = 0; k < s.nz; ++k)
        for (int j = 0; j < s.ny; ++j) {
          detail::row_sums(s, wx, wy, wz, x, zeros.data(), j, k, sum.data(), diagonal.data());
          const std::int64_t row = s.cell_row(j, k);
          if (dirichlet != nullptr)
            for (int i = 0; i < s.nx; ++i) diagonal[i] += dirichlet[row + i];
          if (links && level.row_has_links[j + std::int64_t(s.ny) * k] != 0)
            for (int i = 0; i < s.nx; ++i) sum[i] += link_sum(level, row + i, x);
          for (int i = 0; i < s.nx; ++i)
            r[row + i] = b[row + i] - (diagonal[i] * x[row + i] - sum[i]);
        }
    }
  });
  // An extra part: A_uu = its ground + its links' weights.
  for_extras(level, -1, [&](int u) {
    float diagonal = level.ground[u], sum = 0.0f;
    for (int l = level.link_start[u]; l < level.link_start[u + 1]; ++l) {
      diagonal += level.link_weight[l];
      sum += level.link_weight[l] * x[level.link_to[l]];
    }
    r[u] = b[u] - (diagonal * x[u] - sum);
  });
}

/// out[row] += Σ value · in[column] over the rows of a transfer correction.
void add_correction(const MultigridPreconditioner::SparseRows& rows, const float* in, float* out) {
  const int count = static_cast<int>(rows.row.size());
#pragma omp parallel for schedule(static) if (count >= kParallelThreshold)
  for (int t = 0; t < count; ++t) {
    float sum = 0.0f;
    for (int e = rows.start[t]; e < rows.start[t + 1]; ++e)
      sum += rows.value[e] * in[rows.column[e]];
    out[rows.row[t]] += sum;
  }
}

/// coarse.b = P^T fine.r: the plain trilinear part separably — for each coarse row (J, K) the
/// (up to 4 x 4) fine rows are summed with their y and z weights into one fine-length row,
/// which is then restricted along x — then the part-aware correction, the transpose of
/// prolongation's, so R stays exactly P^T.
void restrict_residual(const Level& fine, const Level& coarse,
                       const std::array<std::vector<Children>, 3>& children) {
  const Eigen::Vector3i n = coarse.cells;
  const int fnx = fine.cells.x();
  const std::int64_t fplane = std::int64_t(fnx) * fine.cells.y();
  const float* r = fine.r;
  float* b = coarse.b;
#pragma omp parallel if (parallel(fine))
  {
    std::vector<float> line(fnx);
#pragma omp for collapse(2) schedule(static)
    for (int K = 0; K < n.z(); ++K)
      for (int J = 0; J < n.y(); ++J) {
        const Children& cz = children[2][K];
        const Children& cy = children[1][J];
        std::fill(line.begin(), line.end(), 0.0f);
        for (int c = 0; c < cz.count; ++c)
          for (int bb = 0; bb < cy.count; ++bb) {
            const float w = cz.weight[c] * cy.weight[bb];
            const float* row = r + cz.fine[c] * fplane + std::int64_t(cy.fine[bb]) * fnx;
            for (int i = 0; i < fnx; ++i) line[i] += w * row[i];
          }
        float* out = b + n.x() * (J + std::int64_t(n.y()) * K);
        for (int I = 0; I < n.x(); ++I) {
          const Children& cx = children[0][I];
          float sum = 0.0f;
          for (int a = 0; a < cx.count; ++a) sum += cx.weight[a] * line[cx.fine[a]];
          out[I] = sum;
        }
      }
  }
  std::fill(b + coarse.size(), b + coarse.unknowns(), 0.0f);
  add_correction(fine.restriction_correction, r, b);
}

/// fine.x += P coarse.x: per fine row, the four coarse rows it interpolates from are
/// first combined with their y/z weights (vectorised), then interpolated along x; then the
/// part-aware correction.
void prolongate_add(const Level& coarse, const Level& fine,
                    const std::array<std::vector<Parents>, 3>& parents) {
  const Eigen::Vector3i n = fine.cells;
  const int cnx = coarse.cells.x();
  const std::int64_t cplane = std::int64_t(cnx) * coarse.cells.y();
  const float* xc = coarse.x;
  float* x = fine.x;
#pragma omp parallel if (parallel(fine))
  {
    std::vector<float> line(cnx);
#pragma omp for collapse(2) schedule(static)
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j) {
        const Parents& pz = parents[2][k];
        const Parents& py = parents[1][j];
        const float* r0 = xc + pz.first * cplane + std::int64_t(py.first) * cnx;
        const float* r1 = xc + pz.first * cplane + std::int64_t(py.second) * cnx;
        const float* r2 = xc + pz.second * cplane + std::int64_t(py.first) * cnx;
        const float* r3 = xc + pz.second * cplane + std::int64_t(py.second) * cnx;
        const float w0 = pz.first_weight * py.first_weight;
        const float w1 = pz.first_weight * py.second_weight;
        const float w2 = pz.second_weight * py.first_weight;
        const float w3 = pz.second_weight * py.second_weight;
        for (int I = 0; I < cnx; ++I) line[I] = w0 * r0[I] + w1 * r1[I] + w2 * r2[I] + w3 * r3[I];
        float* out = x + std::int64_t(n.x()) * (j + std::int64_t(n.y()) * k);
        for (int i = 0; i < n.x(); ++i) {
          const Parents& px = parents[0][i];
          out[i] += px.first_weight * line[px.first] + px.second_weight * line[px.second];
        }
      }
  }
  add_correction(fine.prolongation_correction, xc, x);
}

void zero(float* p, std::int64_t n, bool go) {
#pragma omp parallel for schedule(static) if (go)
  for (std::int64_t i = 0; i < n; ++i) p[i] = 0.0f;
}

/// The fine level's unknowns beyond the plain grid, from A: its extra parts and links (float
/// copies), each cell's diagonal beyond its faces (Dirichlet conductance plus links) and,
/// where A has parts, every unknown's ground (its Dirichlet conductance), as the coarse
/// levels hold them.
void copy_parts(const GridLaplacian& A, Level& fine) {
  const int cells = fine.size();
  const auto& d = A.dirichlet();
  const auto start = A.link_start();
  const auto weight = A.link_weight();
  fine.extras = A.extras();
  fine.extra_cell.assign(A.extra_cells().begin(), A.extra_cells().end());
  fine.cell_extra_start.clear();
  fine.ground.clear();
  if (fine.extras > 0 || A.has_links()) {
    fine.cell_extra_start.assign(cells + 1, 0);
    for (const int c : fine.extra_cell) ++fine.cell_extra_start[c + 1];
    for (int c = 0; c < cells; ++c) fine.cell_extra_start[c + 1] += fine.cell_extra_start[c];
    fine.ground.assign(A.size(), 0.0f);
    if (!d.empty()) std::copy(d.begin(), d.end(), fine.ground.begin());
  }
  // Red–black smoothing needs every link between cells of two colours (face neighbours'
  // parts): a link within a cell, as the §5.1 solve's cloth would make, needs more colours.
  const auto to = A.link_to();
  for (int u = 0; u + 1 < static_cast<int>(start.size()); ++u)
    for (int l = start[u]; l < start[u + 1]; ++l) {
      const int v = to[l];
      const int cu = u < cells ? u : fine.extra_cell[u - cells];
      const int cv = v < cells ? v : fine.extra_cell[v - cells];
      if (colour_of_cell(fine, cu) == colour_of_cell(fine, cv))
        throw Error("MultigridPreconditioner: a link joins unknowns " + std::to_string(u) +
                    " and " + std::to_string(v) + " of cells " + std::to_string(cu) + " and " +
                    std::to_string(cv) +
                    " of one red-black colour; links may only join parts of face neighbours");
    }
  fine.link_start.assign(start.begin(), start.end());
  if (fine.extras > 0 && fine.link_start.empty()) fine.link_start.assign(A.size() + 1, 0);
  fine.link_to.assign(A.link_to().begin(), A.link_to().end());
  fine.link_weight.assign(weight.begin(), weight.end());
  fine.row_has_links.clear();
  if (!A.has_links()) {
    fine.dirichlet.assign(d.begin(), d.end());
    return;
  }
  const Eigen::Vector3i n = fine.cells;
  fine.row_has_links.assign(std::int64_t(n.y()) * n.z(), 0);
  fine.dirichlet.assign(cells, 0.0f);
  for (int c = 0; c < cells; ++c) {
    float beyond = d.empty() ? 0.0f : static_cast<float>(d[c]);
    for (int l = start[c]; l < start[c + 1]; ++l) beyond += weight[l];
    fine.dirichlet[c] = beyond;
    if (start[c + 1] > start[c]) fine.row_has_links[c / n.x()] = 1;
  }
}

/// A level whose unknowns are its cells alone, coupled by faces only: the fused red–black sweep.
bool plain(const Level& level) {
  return !level.has_links() && level.extras == 0;
}

}  // namespace

MultigridPreconditioner::MultigridPreconditioner(MultigridSettings settings,
                                                 std::shared_ptr<MultigridScratch> scratch)
    : m_settings(settings),
      m_scratch(scratch ? std::move(scratch) : std::make_shared<MultigridScratch>()) {
  if (settings.smoothing_sweeps < 1 || settings.coarsest_sweeps < 1)
    throw Error("MultigridPreconditioner: smoothing_sweeps and coarsest_sweeps must be >= 1, got " +
                std::to_string(settings.smoothing_sweeps) + " and " +
                std::to_string(settings.coarsest_sweeps));
  if (settings.near_shell_sweeps < 0 || settings.near_shell_reach < 0)
    throw Error(
        "MultigridPreconditioner: near_shell_sweeps and near_shell_reach must be >= 0, got " +
        std::to_string(settings.near_shell_sweeps) + " and " +
        std::to_string(settings.near_shell_reach));
}

void MultigridPreconditioner::compute(const GridLaplacian& A) {
  const std::uint64_t fingerprint = A.fingerprint();
  if (m_built && fingerprint == m_fingerprint) {
    point_at_weights(A);  // an equal A, perhaps another object
    return;
  }
  m_built = false;  // until the build below completes
  // Level sizes.
  std::vector<Eigen::Vector3i> sizes{A.cells()};
  while (sizes.back().minCoeff() >= kMinCellsToCoarsen)
    sizes.push_back((sizes.back().array() + 1) / 2);
  const bool same = m_levels.size() == sizes.size() && m_levels[0].cells == sizes[0];
  if (!same) m_levels.assign(sizes.size(), Level{});
  for (size_t l = 0; l < sizes.size(); ++l) m_levels[l].cells = sizes[l];
  Level& fine = m_levels[0];
  bool unit = true;
  for (int a = 0; a < 3 && unit; ++a)
    for (const double w : A.weights(a))
      if (w != 0.0 && w != 1.0) {
        unit = false;
        break;
      }
  fine.unit_weights = unit;
  for (int a = 0; a < 3; ++a) {
    const auto& w = A.weights(a);
    const std::int64_t m = static_cast<std::int64_t>(w.size());
    std::vector<float>().swap(fine.weight[a]);  // the fine level owns no float weights
    if (!unit) {
      std::vector<std::uint8_t>().swap(fine.open[a]);
      continue;
    }
    fine.open[a].resize(w.size());
    std::uint8_t* out = fine.open[a].data();
#pragma omp parallel for schedule(static) if (m >= kParallelThreshold)
    for (std::int64_t f = 0; f < m; ++f) out[f] = w[f] != 0.0 ? 1 : 0;
  }
  fine.clamp_for_coarsening = !unit;
  point_at_weights(A);
  copy_parts(A, fine);
  detail::compute_inverse_diagonal(fine);
  auto& lent = m_scratch->coarsening;
  if (lent.size() < m_levels.size()) lent.resize(m_levels.size());
  const auto swap_scratch = [&] {
    for (size_t l = 0; l < m_levels.size(); ++l) {
      m_levels[l].coarse_part.swap(lent[l].coarse_part);
      m_levels[l].scratch_part.swap(lent[l].part);
      m_levels[l].scratch_extra_start.swap(lent[l].extra_start);
      m_levels[l].scratch_simple.swap(lent[l].simple);
    }
  };
  swap_scratch();  // borrow
  for (size_t l = 1; l < m_levels.size(); ++l) detail::coarsen_level(m_levels[l - 1], m_levels[l]);
  swap_scratch();  // and give back
  // Cells at a fractional face (a two-way shell's β), carried down to every level.
  std::vector<std::uint8_t> fractional = detail::fractional_face_cells(fine);
  for (size_t l = 0; l < m_levels.size(); ++l) {
    detail::find_near_shell(m_levels[l], m_settings.near_shell_reach, fractional);
    if (!fractional.empty() && l + 1 < m_levels.size())
      fractional = detail::coarsen_flags(fractional, m_levels[l].cells, m_levels[l + 1].cells);
  }

  m_levels.back().prolongation_correction.clear();
  m_levels.back().restriction_correction.clear();
  m_fingerprint = fingerprint;
  m_built = true;
  ++m_builds;
}

void MultigridPreconditioner::point_at_weights(const GridLaplacian& A) {
  Level& fine = m_levels[0];
  for (int a = 0; a < 3; ++a)
    fine.face_weight[a] = fine.unit_weights ? nullptr : A.weights(a).data();
}

void MultigridPreconditioner::bind_scratch() const {
  auto& buffers = m_scratch->levels;
  if (buffers.size() < m_levels.size()) buffers.resize(m_levels.size());
  for (size_t l = 0; l < m_levels.size(); ++l) {
    const Level& level = m_levels[l];
    const size_t n = static_cast<size_t>(level.unknowns());
    for (auto& v : buffers[l])
      if (v.size() < n) v.resize(n);
    level.x = buffers[l][0].data();
    level.b = buffers[l][1].data();
    level.r = buffers[l][2].data();
  }
}

void MultigridPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  if (m_levels.empty() || r.size() != size())
    throw Error("MultigridPreconditioner::apply: " + std::to_string(r.size()) +
                " entries for a hierarchy of " + std::to_string(size()) +
                " cells (compute(A) first)");
  bind_scratch();
  const int levels = static_cast<int>(m_levels.size());
  {
    const Level& fine = m_levels[0];
    const std::int64_t n = r.size();
    const double* rp = r.data();
    float* b = fine.b;
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
    for (std::int64_t i = 0; i < n; ++i) b[i] = static_cast<float>(rp[i]);
  }
  // Transfer tables of each coarse level (cheap: one entry per cell along an axis).
  std::vector<std::array<std::vector<Parents>, 3>> parents(levels);
  std::vector<std::array<std::vector<Children>, 3>> children(levels);
  for (int l = 1; l < levels; ++l)
    for (int a = 0; a < 3; ++a) {
      const int nf = m_levels[l - 1].cells[a], nc = m_levels[l].cells[a];
      parents[l][a].resize(nf);
      for (int f = 0; f < nf; ++f) parents[l][a][f] = parents_of(f, nc);
      children[l][a] = children_along(nf, nc);
    }

  const int nu = m_settings.smoothing_sweeps;
  // Down: forward smoothing (red, black) from zero, restrict the residual.
  for (int l = 0; l + 1 < levels; ++l) {
    const Level& level = m_levels[l];
    // From x = 0 the first red half sweep reads no neighbour (x_red = b / A_cc) and the
    // black one reads only red cells: together they write every cell, so no zero fill.
    if (plain(level)) {
      fused_sweep(level, 0, true);
      for (int s = 1; s < nu; ++s) fused_sweep(level, 0, false);
    } else {
      first_red_sweep(level);
      half_sweep(level, 1);
      for (int s = 1; s < nu; ++s) {
        half_sweep(level, 0);
        half_sweep(level, 1);
      }
    }
    for (int s = 0; s < m_settings.near_shell_sweeps; ++s) near_shell_sweep(level, true);
    level_residual(level);
    restrict_residual(level, m_levels[l + 1], children[l + 1]);
  }
  // Coarsest: symmetric Gauss–Seidel (red, black, red) from zero.
  {
    const Level& level = m_levels[levels - 1];
    zero(level.x, level.unknowns(), parallel(level));
    for (int s = 0; s < m_settings.coarsest_sweeps; ++s) {
      half_sweep(level, 0);
      half_sweep(level, 1);
      half_sweep(level, 0);
    }
  }
  // Up: correct, then backward smoothing (black, red): the adjoint of the way down.
  for (int l = levels - 2; l >= 0; --l) {
    const Level& level = m_levels[l];
    prolongate_add(m_levels[l + 1], level, parents[l + 1]);
    for (int s = 0; s < m_settings.near_shell_sweeps; ++s) near_shell_sweep(level, false);
    for (int s = 0; s < nu; ++s) {
      if (plain(level)) {
        fused_sweep(level, 1, false);
      } else {
        half_sweep(level, 1);
        half_sweep(level, 0);
      }
    }
  }
  const Level& fine = m_levels[0];
  z.resize(r.size());
  const std::int64_t n = r.size();
  double* zp = z.data();
  const float* x = fine.x;
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
  for (std::int64_t i = 0; i < n; ++i) zp[i] = x[i];
}

}  // namespace shellflow::linear
