#include "shellflow/grid_fluid/pressure_projection.hpp"

#include <algorithm>
#include <cmath>

#include "shellflow/grid_fluid/face_node_transfer.hpp"
#include "shellflow/linear/cholmod_solver.hpp"
#include "shellflow/linear/pcg_mic0_solver.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

PressureProjection::PressureProjection(const grid::UniformGrid& grid, ProjectionSettings settings)
    : m_grid(grid), m_settings(settings) {
  const std::int64_t cells = m_grid.size(Location::Cell);
  for (int a = 0; a < 3; ++a) m_neumann[a].assign(m_grid.size(face_location(a)), 0);
  m_region.assign(cells, -1);
  m_row.assign(cells, -1);
  m_scaled.assign(cells, 0.0);
}

std::int64_t PressureProjection::neighbour(const Eigen::Vector3i& c, int axis, int side) const {
  Eigen::Vector3i nb = c;
  nb[axis] += side == 0 ? -1 : 1;
  if (nb[axis] < 0 || nb[axis] >= m_grid.cells()[axis]) return -1;
  return m_grid.index(Location::Cell, nb);
}

void PressureProjection::mark_neumann(MacGrid& mac, const DomainBoundary& boundary,
                                      const ShellGeometry& shells,
                                      const geometry::ShellBand* band, ProjectionStats& stats) {
  for (int a = 0; a < 3; ++a) {
    auto& flags = m_neumann[a];
    std::fill(flags.begin(), flags.end(), 0);
    const Location loc = face_location(a);
    const Eigen::Vector3i n = m_grid.counts(loc);
    const int b = (a + 1) % 3;
    const int c = (a + 2) % 3;
    // Wall and inflow faces of the domain.
    for (int side = 0; side < 2; ++side) {
      if (boundary.side(a, side).type == BoundaryType::Open) continue;
      Eigen::Vector3i ijk;
      ijk[a] = side == 0 ? 0 : m_grid.cells()[a];
      for (int j = 0; j < n[b]; ++j)
        for (int k = 0; k < n[c]; ++k) {
          ijk[b] = j;
          ijk[c] = k;
          flags[m_grid.index(loc, ijk)] = 1;
        }
    }
    if (band == nullptr || shells.empty()) continue;
    // Fig. 5: a ray between the two cell centres that meets a shell closes the face.
    const auto list = band->samples(loc);
    const std::int64_t m = static_cast<std::int64_t>(list.size());
    auto& u = mac.face_velocity(a);
    std::int64_t closed = 0;
    const double half = 0.5 * m_grid.dx();
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : closed)
    for (std::int64_t s = 0; s < m; ++s) {
      const std::int64_t f = list[s];
      const Eigen::Vector3i ijk = m_grid.coordinates(loc, f);
      if (ijk[a] == 0 || ijk[a] == m_grid.cells()[a]) continue;
      const Eigen::Vector3d y = m_grid.position(loc, ijk);
      Eigen::Vector3d c0 = y;
      Eigen::Vector3d c1 = y;
      c0[a] -= half;
      c1[a] += half;
      if (shells.visible(c0, c1)) continue;
      flags[f] = 1;
      u[f] = shells.object_velocity(c0, c1)[a];  // §4.3: the (effective) object velocity
      ++closed;
    }
    stats.shell_neumann_faces += closed;
  }
}

void PressureProjection::flood_fill(const DomainBoundary& boundary) {
  const std::int64_t cells = m_grid.size(Location::Cell);
  std::fill(m_region.begin(), m_region.end(), -1);
  m_enclosed.clear();
  std::vector<std::int64_t> stack;
  int regions = 0;
  std::vector<std::int64_t> counts;
  for (std::int64_t seed = 0; seed < cells; ++seed) {
    if (m_region[seed] >= 0) continue;
    const int r = regions++;
    bool open = false;
    std::int64_t size = 0;
    m_region[seed] = r;
    stack.push_back(seed);
    while (!stack.empty()) {
      const std::int64_t cell = stack.back();
      stack.pop_back();
      ++size;
      const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, cell);
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          if (m_neumann[a][face_of(c, a, side)] != 0) continue;
          const std::int64_t nb = neighbour(c, a, side);
          if (nb < 0) {
            open = open || boundary.side(a, side).type == BoundaryType::Open;
            continue;
          }
          if (m_region[nb] >= 0) continue;
          m_region[nb] = r;
          stack.push_back(nb);
        }
    }
    m_enclosed.push_back(open ? 0 : 1);
    counts.push_back(size);
  }
  // Cells of each region, in cell order (CSR).
  m_region_start.assign(regions + 1, 0);
  for (int r = 0; r < regions; ++r) m_region_start[r + 1] = m_region_start[r] + counts[r];
  m_region_cells.resize(cells);
  std::vector<std::int64_t> fill(m_region_start.begin(), m_region_start.end() - 1);
  for (std::int64_t cell = 0; cell < cells; ++cell) m_region_cells[fill[m_region[cell]]++] = cell;
}

void PressureProjection::correct_compatibility(MacGrid& mac, ProjectionStats& stats) {
  const int regions = static_cast<int>(m_enclosed.size());
  std::vector<std::uint8_t> corrected(regions, 0);
  struct BoundaryFace {
    int axis;
    std::int64_t face;
    double outward;  ///< +1: the region lies on the face's min side
  };
  std::vector<BoundaryFace> faces;
  // Smallest first: a pocket is corrected through the faces it shares with whatever
  // surrounds it, and the surrounding region then through its other faces (walls).
  std::vector<int> order;
  for (int r = 0; r < regions; ++r)
    if (m_enclosed[r] != 0) order.push_back(r);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
    return m_region_start[x + 1] - m_region_start[x] < m_region_start[y + 1] - m_region_start[y];
  });
  for (const int r : order) {
    double net = 0.0;
    faces.clear();
    std::vector<BoundaryFace> shared;  // faces shared with corrected enclosed regions
    for (std::int64_t s = m_region_start[r]; s < m_region_start[r + 1]; ++s) {
      const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, m_region_cells[s]);
      net += mac.outward_flux(c);
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          const std::int64_t f = face_of(c, a, side);
          if (m_neumann[a][f] == 0) continue;
          const std::int64_t nb = neighbour(c, a, side);
          if (nb >= 0 && m_region[nb] == r) continue;  // inside the region: cancels
          const BoundaryFace bf{a, f, side == 1 ? 1.0 : -1.0};
          if (nb >= 0 && corrected[m_region[nb]] != 0) {
            shared.push_back(bf);
          } else {
            faces.push_back(bf);
          }
        }
    }
    if (faces.empty()) faces = shared;  // boxed in by corrected regions: no better choice
    corrected[r] = 1;
    stats.max_compatibility_flux = std::max(stats.max_compatibility_flux, std::abs(net));
    if (faces.empty() || net == 0.0) continue;
    // §4.3: net flow per unit area, removed from every boundary face (equal areas dx^2).
    const double delta = net / static_cast<double>(faces.size());
    for (const auto& bf : faces) mac.face_velocity(bf.axis)[bf.face] -= bf.outward * delta;
  }
}

void PressureProjection::solve_region(int r, const MacGrid& mac, const DomainBoundary& boundary,
                                      double scale, ProjectionStats& stats) {
  const std::int64_t begin = m_region_start[r];
  const int size = static_cast<int>(m_region_start[r + 1] - begin);
  const bool enclosed = m_enclosed[r] != 0;
  for (int k = 0; k < size; ++k) m_row[m_region_cells[begin + k]] = k;

  Eigen::VectorXd b(size);
  Eigen::VectorXd x(size);
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<size_t>(size) * 7);
  for (int k = 0; k < size; ++k) {
    const std::int64_t cell = m_region_cells[begin + k];
    const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, cell);
    double diag = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        if (m_neumann[a][face_of(c, a, side)] != 0) continue;
        const std::int64_t nb = neighbour(c, a, side);
        diag += 1.0;
        if (nb >= 0) triplets.emplace_back(k, m_row[nb], -1.0);
        (void)boundary;  // outside the domain behind a non-Neumann face: Dirichlet p = 0
      }
    triplets.emplace_back(k, k, diag);
    b[k] = -mac.outward_flux(c);
    x[k] = m_scaled[cell];
  }
  if (enclosed) b.array() -= b.mean();  // consistent to round-off after the correction
  if (b.lpNorm<Eigen::Infinity>() == 0.0) {
    for (int k = 0; k < size; ++k) m_scaled[m_region_cells[begin + k]] = 0.0;
    return;
  }
  if (m_settings.solver == PressureSolver::Cholmod && enclosed) {
    triplets.emplace_back(0, 0, 1.0);  // fixes the constant; exact for a consistent b
  }
  linear::SparseMatrix A(size, size);
  A.setFromTriplets(triplets.begin(), triplets.end());
  A.makeCompressed();

  linear::SolveStats solve;
  if (m_settings.solver == PressureSolver::Cholmod) {
    linear::CholmodSolver direct;
    direct.compute(A);
    solve = direct.solve(b, x);
  } else {
    // |r|_2 <= tol |b|_2, and also |r|_inf <= |r|_2 <= tol · max|u*| (the divergence bound).
    const double tolerance =
        std::min(m_settings.tolerance, m_settings.tolerance * scale / b.norm());
    linear::PcgMic0Solver pcg;
    pcg.compute(A);
    solve = pcg.solve(b, x, tolerance, m_settings.max_iterations);
    solve.converged = solve.converged || solve.relative_residual <= tolerance;
  }
  stats.iterations += solve.iterations;
  stats.max_region_iterations = std::max(stats.max_region_iterations, solve.iterations);
  stats.relative_residual = std::max(stats.relative_residual, solve.relative_residual);
  stats.converged = stats.converged && solve.converged;
  for (int k = 0; k < size; ++k) m_scaled[m_region_cells[begin + k]] = x[k];
}

ProjectionStats PressureProjection::project(MacGrid& mac, double dt,
                                            const DomainBoundary& boundary,
                                            const ShellGeometry& shells,
                                            const geometry::ShellBand* band) {
  ProjectionStats stats;
  apply_boundary_velocities(mac, boundary);
  mark_neumann(mac, boundary, shells, band, stats);
  flood_fill(boundary);
  const int regions = static_cast<int>(m_enclosed.size());
  stats.regions = regions;
  for (const auto e : m_enclosed) stats.enclosed_regions += e;
  correct_compatibility(mac, stats);

  // Solve, update the faces, and measure; a PCG solve whose largest cell divergence is
  // still above tolerance × max|u| (its stopping test bounds the 2-norm against max|u*|)
  // is refined by projecting the remaining divergence (iterative refinement, warm start 0).
  std::vector<double> total(m_scaled.size(), 0.0);
  double max_div = 0.0;
  double speed = 0.0;
  const int passes = m_settings.solver == PressureSolver::Pcg ? 3 : 1;
  for (int pass = 0; pass < passes; ++pass) {
    const double scale = std::max(mac.max_face_speed(), 1e-300);
    if (pass > 0) std::fill(m_scaled.begin(), m_scaled.end(), 0.0);
    for (int r = 0; r < regions; ++r) solve_region(r, mac, boundary, scale, stats);
    apply_pressure(mac);
    for (size_t i = 0; i < total.size(); ++i) total[i] += m_scaled[i];
    max_div = max_cell_divergence(mac);
    speed = mac.max_face_speed();
    if (max_div <= m_settings.tolerance * speed) break;
  }
  m_scaled = total;
  stats.max_relative_divergence = speed > 0.0 ? max_div / speed : 0.0;
  const double to_pressure = m_grid.dx() / dt;
  auto& p = mac.pressure();
  for (size_t i = 0; i < p.size(); ++i) p[i] = m_scaled[i] * to_pressure;
  return stats;
}

void PressureProjection::apply_pressure(MacGrid& mac) const {
  // u = u* − (p'_+ − p'_−) on every non-Neumann face (eq. (3)); p' = 0 outside open faces.
  for (int a = 0; a < 3; ++a) {
    const Location loc = face_location(a);
    auto& u = mac.face_velocity(a);
    const auto& flags = m_neumann[a];
    const std::int64_t count = m_grid.size(loc);
    const Eigen::Vector3i cells = m_grid.cells();
#pragma omp parallel for schedule(static)
    for (std::int64_t f = 0; f < count; ++f) {
      if (flags[f] != 0) continue;
      const Eigen::Vector3i ijk = m_grid.coordinates(loc, f);
      Eigen::Vector3i lo = ijk;
      lo[a] -= 1;
      const double p_minus = ijk[a] > 0 ? m_scaled[m_grid.index(Location::Cell, lo)] : 0.0;
      const double p_plus = ijk[a] < cells[a] ? m_scaled[m_grid.index(Location::Cell, ijk)] : 0.0;
      u[f] -= p_plus - p_minus;
    }
  }
}

double PressureProjection::max_cell_divergence(const MacGrid& mac) const {
  const std::int64_t cells = m_grid.size(Location::Cell);
  double max_div = 0.0;
#pragma omp parallel for reduction(max : max_div)
  for (std::int64_t cell = 0; cell < cells; ++cell)
    max_div = std::max(max_div,
                       std::abs(mac.outward_flux(m_grid.coordinates(Location::Cell, cell))));
  return max_div;
}

}  // namespace shellflow::grid_fluid
