#include "shellflow/linear/multigrid_preconditioner.hpp"

#include <algorithm>
#include <string>

#include "cell_stencil.hpp"
#include "parallel_threshold.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::linear {
namespace {

using detail::kParallelThreshold;
using Level = MultigridPreconditioner::Level;

// Coarsen while every axis has at least this many cells (coarsest: 4–7 on the shortest).
constexpr int kMinCellsToCoarsen = 8;

/// The two coarse parents of fine cell f along one axis under trilinear interpolation
/// between cell centres: f/2 with weight 3/4 and its neighbour on f's side with 1/4, or
/// f/2 alone (weight 1) where that neighbour lies outside the domain.
struct Parents {
  int first, second;
  float first_weight, second_weight;
};

Parents parents_of(int f, int coarse) {
  const int near = f / 2;
  const int far = (f % 2 == 1) ? near + 1 : near - 1;
  if (far < 0 || far >= coarse) return {near, near, 1.0f, 0.0f};
  return {near, far, 0.75f, 0.25f};
}

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

/// Calls f(wx, wy, wz) with the level's face weights: one byte per face when every weight
/// is 0 or 1 (the projection's fine grid: a third of the memory traffic of floats), floats
/// otherwise.
template <class F>
void with_weights(const Level& level, F&& f) {
  if (level.unit_weights) {
    f(level.open[0].data(), level.open[1].data(), level.open[2].data());
  } else {
    f(level.weight[0].data(), level.weight[1].data(), level.weight[2].data());
  }
}

void compute_inverse_diagonal(Level& level) {
  const auto s = detail::stencil_of(level.cells);
  level.inverse_diagonal.resize(level.cells.prod());
  const float* x = level.inverse_diagonal.data();  // not read: the sum is ignored
  float* out = level.inverse_diagonal.data();
  const float* dirichlet = level.dirichlet.empty() ? nullptr : level.dirichlet.data();
  // out and dirichlet are captured by value: clang 14 refuses a by-reference capture of
  // the function's locals from a lambda inside an OpenMP loop inside a generic lambda
  // ("reference to local variable declared in enclosing function"); g++ accepts both.
  with_weights(level, [&, out, dirichlet](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel for collapse(2) schedule(static) if (parallel(level))
    for (int k = 0; k < s.nz; ++k)
      for (int j = 0; j < s.ny; ++j)
        detail::for_row(s, wx, wy, wz, x, j, k, 0, 1, [&](int, std::int64_t c, float d, float) {
          if (dirichlet != nullptr) d += dirichlet[c];
          out[c] = d > 0.0f ? 1.0f / d : 0.0f;  // isolated cell: left at 0
        });
  });
}

/// The near_only bits of a level that has a coarser one (see Level): along axis d, cell
/// i's far parent lies on the side of i's odd/even neighbour (i + 1 for odd i, i - 1 for
/// even), as in parents_of; a closed face (weight 0) between them drops that parent.
void compute_near_only(Level& level, const Eigen::Vector3i& coarse_cells) {
  const Eigen::Vector3i n = level.cells;
  level.near_only.assign(n.prod(), 0);
  level.row_near_only.assign(std::int64_t(n.y()) * n.z(), 0);
  const auto weight = [&](int a, std::int64_t f) {
    return level.unit_weights ? float(level.open[a][f]) : level.weight[a][f];
  };
#pragma omp parallel for collapse(2) schedule(static) if (parallel(level))
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j) {
      std::uint8_t any = 0;
      for (int i = 0; i < n.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        std::uint8_t bits = 0;
        for (int a = 0; a < 3; ++a) {
          const Parents p = parents_of(c[a], coarse_cells[a]);
          if (p.second_weight == 0.0f) continue;
          Eigen::Vector3i face = c;  // the face between c and its neighbour towards `second`
          if (c[a] % 2 == 1) face[a] += 1;
          Eigen::Vector3i faces = n;
          faces[a] += 1;
          const std::int64_t f =
              face.x() + std::int64_t(faces.x()) * (face.y() + std::int64_t(faces.y()) * face.z());
          if (weight(a, f) == 0.0f) bits |= std::uint8_t(1 << a);
        }
        level.near_only[i + std::int64_t(n.x()) * (j + std::int64_t(n.y()) * k)] = bits;
        any |= bits;
      }
      level.row_near_only[j + std::int64_t(n.y()) * k] = any != 0;
    }
}

/// Parents of cell c along axis a, with the far one dropped where near_only says so.
Parents parents_near_only(const Parents& p, std::uint8_t bits, int a) {
  if ((bits >> a & 1) == 0) return p;
  return {p.first, p.first, 1.0f, 0.0f};
}

/// Coarse face weights: half the sum of the fine face weights each coarse face covers.
void coarsen_weights(const Level& fine, Level& coarse) {
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3i fine_faces = fine.cells;
    fine_faces[a] += 1;
    Eigen::Vector3i coarse_faces = coarse.cells;
    coarse_faces[a] += 1;
    auto& out = coarse.weight[a];
    out.resize(coarse_faces.prod());
    const bool go = coarse_faces.prod() >= kParallelThreshold;
    const auto fine_weight = [&](std::int64_t f) {
      return fine.unit_weights ? float(fine.open[a][f]) : fine.weight[a][f];
    };
#pragma omp parallel for collapse(2) schedule(static) if (go)
    for (int K = 0; K < coarse_faces.z(); ++K)
      for (int J = 0; J < coarse_faces.y(); ++J)
        for (int I = 0; I < coarse_faces.x(); ++I) {
          const Eigen::Vector3i C(I, J, K);
          // Fine range per axis: the coinciding face along a, two children across.
          int lo[3], hi[3];
          for (int d = 0; d < 3; ++d) {
            if (d == a) {
              lo[d] = hi[d] = std::min(2 * C[d], fine.cells[d]);
            } else {
              lo[d] = 2 * C[d];
              hi[d] = std::min(2 * C[d] + 1, fine.cells[d] - 1);
            }
          }
          float sum = 0.0f;
          for (int k = lo[2]; k <= hi[2]; ++k)
            for (int j = lo[1]; j <= hi[1]; ++j)
              for (int i = lo[0]; i <= hi[0]; ++i)
                sum += fine_weight(i + std::int64_t(fine_faces.x()) *
                                           (j + std::int64_t(fine_faces.y()) * k));
          out[I + std::int64_t(coarse_faces.x()) * (J + std::int64_t(coarse_faces.y()) * K)] =
              0.5f * sum;
        }
  }
}

/// Coarse Dirichlet conductances: half the sum over each coarse cell's children (as faces).
void coarsen_dirichlet(const Level& fine, Level& coarse) {
  if (fine.dirichlet.empty()) {
    coarse.dirichlet.clear();
    return;
  }
  const Eigen::Vector3i n = coarse.cells, f = fine.cells;
  coarse.dirichlet.assign(n.prod(), 0.0f);
#pragma omp parallel for collapse(2) schedule(static) if (parallel(coarse))
  for (int K = 0; K < n.z(); ++K)
    for (int J = 0; J < n.y(); ++J)
      for (int I = 0; I < n.x(); ++I) {
        float sum = 0.0f;
        for (int k = 2 * K; k <= std::min(2 * K + 1, f.z() - 1); ++k)
          for (int j = 2 * J; j <= std::min(2 * J + 1, f.y() - 1); ++j)
            for (int i = 2 * I; i <= std::min(2 * I + 1, f.x() - 1); ++i)
              sum += fine.dirichlet[i + std::int64_t(f.x()) * (j + std::int64_t(f.y()) * k)];
        coarse.dirichlet[I + std::int64_t(n.x()) * (J + std::int64_t(n.y()) * K)] = 0.5f * sum;
      }
}

/// One red (color 0) or black (color 1) Gauss–Seidel half sweep: x_c = (b_c + Σ w x_nb) / A_cc
/// on the cells with (i + j + k) % 2 == color; cells of one color only read the other's.
void half_sweep(const Level& level, int color) {
  const auto s = detail::stencil_of(level.cells);
  float* x = level.x.data();
  const float* b = level.b.data();
  const float* inverse = level.inverse_diagonal.data();
  with_weights(level, [&](const auto* wx, const auto* wy, const auto* wz) {
#pragma omp parallel if (parallel(level))
    {
      // Whole rows in a vectorised pass into `sum`, then only this colour written back:
      // its neighbours are all of the other colour, which this half sweep leaves alone.
      std::vector<float> sum(s.nx), zeros(s.nx, 0.0f);
#pragma omp for collapse(2) schedule(static)
      for (int k = 0; k < s.nz; ++k)
        for (int j = 0; j < s.ny; ++j) {
          detail::row_sums(s, wx, wy, wz, static_cast<const float*>(x), zeros.data(), j, k,
                           sum.data(), static_cast<float*>(nullptr));
          const std::int64_t row = s.cell_row(j, k);
          for (int i = (j + k + color) & 1; i < s.nx; i += 2)
            x[row + i] = (b[row + i] + sum[i]) * inverse[row + i];
        }
    }
  });
}

/// The red half sweep from x = 0: x_c = b_c / A_cc on the red cells (black ones untouched).
void first_red_sweep(const Level& level) {
  const Eigen::Vector3i n = level.cells;
  float* x = level.x.data();
  const float* b = level.b.data();
  const float* inverse = level.inverse_diagonal.data();
#pragma omp parallel for collapse(2) schedule(static) if (parallel(level))
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j) {
      const std::int64_t row = std::int64_t(n.x()) * (j + std::int64_t(n.y()) * k);
      for (int i = (j + k) & 1; i < n.x(); i += 2) x[row + i] = b[row + i] * inverse[row + i];
    }
}

/// r = b − A x on a level.
void level_residual(const Level& level) {
  const auto s = detail::stencil_of(level.cells);
  const float* x = level.x.data();
  const float* b = level.b.data();
  float* r = level.r.data();
  const float* dirichlet = level.dirichlet.empty() ? nullptr : level.dirichlet.data();
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
          for (int i = 0; i < s.nx; ++i)
            r[row + i] = b[row + i] - (diagonal[i] * x[row + i] - sum[i]);
        }
    }
  });
}

/// Weight of a fine cell with parents p towards coarse cell `parent` along one axis.
float weight_towards(const Parents& p, int parent) {
  return (p.first == parent ? p.first_weight : 0.0f) +
         (p.second == parent ? p.second_weight : 0.0f);
}

/// Restriction's correction for one fine row (child c of K along z, bb of J along y) with
/// near_only cells: each such cell's contribution to coarse row (J, K) moves from the
/// standard weights (already summed) to its own, so that R stays exactly P^T.
void correct_near_only(const Level& fine, const Children& cz, int c, int K, const Children& cy,
                       int bb, int J, const Eigen::Vector3i& coarse_cells, float* out) {
  const std::int64_t fnx = fine.cells.x();
  const std::int64_t row = fnx * (cy.fine[bb] + std::int64_t(fine.cells.y()) * cz.fine[c]);
  const Parents pz = parents_of(cz.fine[c], coarse_cells.z());
  const Parents py = parents_of(cy.fine[bb], coarse_cells.y());
  const float standard_zy = cz.weight[c] * cy.weight[bb];
  for (int i = 0; i < fnx; ++i) {
    const std::uint8_t bits = fine.near_only[row + i];
    if (bits == 0) continue;
    const float wz = weight_towards(parents_near_only(pz, bits, 2), K);
    const float wy = weight_towards(parents_near_only(py, bits, 1), J);
    const Parents px = parents_of(i, coarse_cells.x());
    const Parents qx = parents_near_only(px, bits, 0);
    const float r = fine.r[row + i];
    for (const auto& [I, w] :
         {std::pair{px.first, px.first_weight}, std::pair{px.second, px.second_weight}}) {
      if (w == 0.0f) continue;
      out[I] += (wz * wy * weight_towards(qx, I) - standard_zy * w) * r;
    }
  }
}

/// coarse.b = P^T fine.r, separably: for each coarse row (J, K) the (up to 4 x 4) fine rows
/// are summed with their y and z weights into one fine-length row, which is then restricted
/// along x. Same weights as the tensor product, so still exactly P^T.
void restrict_residual(const Level& fine, const Level& coarse,
                       const std::array<std::vector<Children>, 3>& children) {
  const Eigen::Vector3i n = coarse.cells;
  const int fnx = fine.cells.x();
  const std::int64_t fplane = std::int64_t(fnx) * fine.cells.y();
  const float* r = fine.r.data();
  float* b = coarse.b.data();
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
        for (int c = 0; c < cz.count; ++c)
          for (int bb = 0; bb < cy.count; ++bb)
            if (fine.row_near_only[cy.fine[bb] + std::int64_t(fine.cells.y()) * cz.fine[c]])
              correct_near_only(fine, cz, c, K, cy, bb, J, n, out);
      }
  }
}

/// fine.x += P coarse.x: per fine row, the four coarse rows it interpolates from are
/// first combined with their y/z weights (vectorised), then interpolated along x.
void prolongate_add(const Level& coarse, const Level& fine,
                    const std::array<std::vector<Parents>, 3>& parents) {
  const Eigen::Vector3i n = fine.cells;
  const int cnx = coarse.cells.x();
  const std::int64_t cplane = std::int64_t(cnx) * coarse.cells.y();
  const float* xc = coarse.x.data();
  float* x = fine.x.data();
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
        const std::int64_t row = std::int64_t(n.x()) * (j + std::int64_t(n.y()) * k);
        float* out = x + row;
        const bool masked = fine.row_near_only[j + std::int64_t(n.y()) * k] != 0;
        for (int i = 0; i < n.x(); ++i) {
          const std::uint8_t bits = masked ? fine.near_only[row + i] : 0;
          if (bits == 0) {
            const Parents& px = parents[0][i];
            out[i] += px.first_weight * line[px.first] + px.second_weight * line[px.second];
            continue;
          }
          // A parent across a closed face is dropped: the tensor product, term by term.
          const Parents qx = parents_near_only(parents[0][i], bits, 0);
          const Parents qy = parents_near_only(py, bits, 1);
          const Parents qz = parents_near_only(pz, bits, 2);
          float sum = 0.0f;
          for (const auto& [zc, zw] :
               {std::pair{qz.first, qz.first_weight}, std::pair{qz.second, qz.second_weight}})
            for (const auto& [yc, yw] :
                 {std::pair{qy.first, qy.first_weight}, std::pair{qy.second, qy.second_weight}}) {
              const float* r = xc + zc * cplane + std::int64_t(yc) * cnx;
              sum += zw * yw * (qx.first_weight * r[qx.first] + qx.second_weight * r[qx.second]);
            }
          out[i] += sum;
        }
      }
  }
}

void zero(std::vector<float>& v, bool go) {
  const std::int64_t n = static_cast<std::int64_t>(v.size());
  float* p = v.data();
#pragma omp parallel for schedule(static) if (go)
  for (std::int64_t i = 0; i < n; ++i) p[i] = 0.0f;
}

}  // namespace

MultigridPreconditioner::MultigridPreconditioner(MultigridSettings settings)
    : m_settings(settings) {
  if (settings.smoothing_sweeps < 1 || settings.coarsest_sweeps < 1)
    throw Error("MultigridPreconditioner: smoothing_sweeps and coarsest_sweeps must be >= 1, got " +
                std::to_string(settings.smoothing_sweeps) + " and " +
                std::to_string(settings.coarsest_sweeps));
}

void MultigridPreconditioner::compute(const GridLaplacian& A) {
  // Level sizes.
  std::vector<Eigen::Vector3i> sizes{A.cells()};
  while (sizes.back().minCoeff() >= kMinCellsToCoarsen)
    sizes.push_back((sizes.back().array() + 1) / 2);
  const bool same = m_levels.size() == sizes.size() && m_levels[0].cells == sizes[0];
  if (!same) m_levels.assign(sizes.size(), Level{});
  for (size_t l = 0; l < sizes.size(); ++l) {
    Level& level = m_levels[l];
    level.cells = sizes[l];
    const std::int64_t n = sizes[l].prod();
    level.x.resize(n);
    level.b.resize(n);
    level.r.resize(n);
  }
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
    if (unit) {
      fine.weight[a].clear();
      fine.open[a].resize(w.size());
      std::uint8_t* out = fine.open[a].data();
#pragma omp parallel for schedule(static) if (m >= kParallelThreshold)
      for (std::int64_t f = 0; f < m; ++f) out[f] = w[f] != 0.0 ? 1 : 0;
    } else {
      fine.open[a].clear();
      fine.weight[a].resize(w.size());
      float* out = fine.weight[a].data();
#pragma omp parallel for schedule(static) if (m >= kParallelThreshold)
      for (std::int64_t f = 0; f < m; ++f) out[f] = static_cast<float>(w[f]);
    }
  }
  fine.dirichlet.assign(A.dirichlet().begin(), A.dirichlet().end());
  compute_inverse_diagonal(fine);
  for (size_t l = 1; l < m_levels.size(); ++l) {
    compute_near_only(m_levels[l - 1], m_levels[l].cells);
    coarsen_weights(m_levels[l - 1], m_levels[l]);
    coarsen_dirichlet(m_levels[l - 1], m_levels[l]);
    compute_inverse_diagonal(m_levels[l]);
  }
}

void MultigridPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  if (m_levels.empty() || r.size() != size())
    throw Error("MultigridPreconditioner::apply: " + std::to_string(r.size()) +
                " entries for a hierarchy of " + std::to_string(size()) +
                " cells (compute(A) first)");
  const int levels = static_cast<int>(m_levels.size());
  {
    const Level& fine = m_levels[0];
    const std::int64_t n = r.size();
    const double* rp = r.data();
    float* b = fine.b.data();
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
    first_red_sweep(level);
    half_sweep(level, 1);
    for (int s = 1; s < nu; ++s) {
      half_sweep(level, 0);
      half_sweep(level, 1);
    }
    level_residual(level);
    restrict_residual(level, m_levels[l + 1], children[l + 1]);
  }
  // Coarsest: symmetric Gauss–Seidel (red, black, red) from zero.
  {
    const Level& level = m_levels[levels - 1];
    zero(level.x, parallel(level));
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
    for (int s = 0; s < nu; ++s) {
      half_sweep(level, 1);
      half_sweep(level, 0);
    }
  }
  const Level& fine = m_levels[0];
  z.resize(r.size());
  const std::int64_t n = r.size();
  double* zp = z.data();
  const float* x = fine.x.data();
#pragma omp parallel for schedule(static) if (n >= kParallelThreshold)
  for (std::int64_t i = 0; i < n; ++i) zp[i] = x[i];
}

}  // namespace shellflow::linear
