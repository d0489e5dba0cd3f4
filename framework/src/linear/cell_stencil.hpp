#pragma once
// The 7-point cell stencil of GridLaplacian, shared by its double-precision products and
// the single-precision multigrid levels: for the cells of one grid row (j, k) it hands
// each cell's diagonal (sum of its six face weights) and Σ_faces w_f x_nb(f) to a
// callback, neighbours outside the domain counting as 0 (Dirichlet ghosts).

#include <Eigen/Core>
#include <cstdint>

namespace shellflow::linear::detail {

/// Face and cell offsets of one grid (cells n), in the GridLaplacian layout.
struct CellStencil {
  int nx, ny, nz;
  std::int64_t cell_row(int j, int k) const {
    return std::int64_t(nx) * (j + std::int64_t(ny) * k);
  }
  std::int64_t face_x_row(int j, int k) const {
    return std::int64_t(nx + 1) * (j + std::int64_t(ny) * k);
  }
  std::int64_t face_y_row(int j, int k) const {
    return std::int64_t(nx) * (j + std::int64_t(ny + 1) * k);
  }
  std::int64_t face_z_row(int j, int k) const {
    return std::int64_t(nx) * (j + std::int64_t(ny) * k);
  }
  std::int64_t plane() const { return std::int64_t(nx) * ny; }
};

inline CellStencil stencil_of(const Eigen::Vector3i& n) {
  return CellStencil{n.x(), n.y(), n.z()};
}

/// Calls f(i, cell, diagonal, neighbour_sum) for i = first, first + step, ... < nx on row
/// (j, k). W: weight type, X: value type.
template <class W, class X, class F>
inline void for_row(const CellStencil& s, const W* wx, const W* wy, const W* wz, const X* x, int j,
                    int k, int first, int step, F&& f) {
  const std::int64_t row = s.cell_row(j, k);
  const W* fx = wx + s.face_x_row(j, k);
  const W* fy_lo = wy + s.face_y_row(j, k);
  const W* fy_hi = fy_lo + s.nx;
  const W* fz_lo = wz + s.face_z_row(j, k);
  const W* fz_hi = fz_lo + s.plane();
  const X* xc = x + row;
  const X* x_down = j > 0 ? xc - s.nx : nullptr;
  const X* x_up = j + 1 < s.ny ? xc + s.nx : nullptr;
  const X* x_back = k > 0 ? xc - s.plane() : nullptr;
  const X* x_front = k + 1 < s.nz ? xc + s.plane() : nullptr;
  for (int i = first; i < s.nx; i += step) {
    const X diagonal =
        X(fx[i]) + X(fx[i + 1]) + X(fy_lo[i]) + X(fy_hi[i]) + X(fz_lo[i]) + X(fz_hi[i]);
    X sum = 0;
    if (i > 0) sum += X(fx[i]) * xc[i - 1];
    if (i + 1 < s.nx) sum += X(fx[i + 1]) * xc[i + 1];
    if (x_down) sum += X(fy_lo[i]) * x_down[i];
    if (x_up) sum += X(fy_hi[i]) * x_up[i];
    if (x_back) sum += X(fz_lo[i]) * x_back[i];
    if (x_front) sum += X(fz_hi[i]) * x_front[i];
    f(i, row + i, diagonal, sum);
  }
}

/// The same for a whole row in one vectorisable pass (no per-cell branches): sum[i] =
/// Σ_faces w_f x_nb(f) and, when `diagonal` is not null, diagonal[i] = Σ_faces w_f, for
/// i in [0, nx). `zeros` holds nx zeros (stands in for the rows beyond the domain).
template <class W, class X>
inline void row_sums(const CellStencil& s, const W* __restrict wx, const W* __restrict wy,
                     const W* __restrict wz, const X* __restrict x, const X* __restrict zeros,
                     int j, int k, X* __restrict sum, X* __restrict diagonal) {
  const std::int64_t row = s.cell_row(j, k);
  const W* __restrict fx = wx + s.face_x_row(j, k);
  const W* __restrict fy_lo = wy + s.face_y_row(j, k);
  const W* __restrict fy_hi = fy_lo + s.nx;
  const W* __restrict fz_lo = wz + s.face_z_row(j, k);
  const W* __restrict fz_hi = fz_lo + s.plane();
  const X* __restrict xc = x + row;
  const X* __restrict x_down = j > 0 ? xc - s.nx : zeros;
  const X* __restrict x_up = j + 1 < s.ny ? xc + s.nx : zeros;
  const X* __restrict x_back = k > 0 ? xc - s.plane() : zeros;
  const X* __restrict x_front = k + 1 < s.nz ? xc + s.plane() : zeros;
  const int nx = s.nx;
  for (int i = 0; i < nx; ++i)
    sum[i] = X(fy_lo[i]) * x_down[i] + X(fy_hi[i]) * x_up[i] + X(fz_lo[i]) * x_back[i] +
             X(fz_hi[i]) * x_front[i];
  for (int i = 1; i < nx; ++i) sum[i] += X(fx[i]) * xc[i - 1];
  for (int i = 0; i + 1 < nx; ++i) sum[i] += X(fx[i + 1]) * xc[i + 1];
  if (diagonal != nullptr)
    for (int i = 0; i < nx; ++i)
      diagonal[i] = X(fx[i]) + X(fx[i + 1]) + X(fy_lo[i]) + X(fy_hi[i]) + X(fz_lo[i]) + X(fz_hi[i]);
}

}  // namespace shellflow::linear::detail
