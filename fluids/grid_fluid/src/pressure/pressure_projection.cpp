#include "shellflow/grid_fluid/pressure/pressure_projection.hpp"

#include <algorithm>
#include <cmath>

#include "shellflow/grid_fluid/mac/face_node_transfer.hpp"
#include "shellflow/linear/cholmod_solver.hpp"
#include "shellflow/linear/laplacian_null_space.hpp"
#include "shellflow/linear/pcg_mic0_solver.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

PressureProjection::PressureProjection(const grid::UniformGrid& grid, ProjectionSettings settings,
                                       SolveScratch scratch)
    : m_grid(grid),
      m_settings(settings),
      m_multigrid(linear::MultigridSettings{}, scratch.multigrid),
      m_scratch(std::move(scratch)) {
  const std::int64_t cells = m_grid.size(Location::Cell);
  for (int a = 0; a < 3; ++a) m_neumann[a].assign(m_grid.size(face_location(a)), 0);
  m_scaled.setZero(cells);
}

std::int64_t PressureProjection::neighbour(const Eigen::Vector3i& c, int axis, int side) const {
  Eigen::Vector3i nb = c;
  nb[axis] += side == 0 ? -1 : 1;
  if (nb[axis] < 0 || nb[axis] >= m_grid.cells()[axis]) return -1;
  return m_grid.index(Location::Cell, nb);
}

void PressureProjection::mark_neumann(MacGrid& mac, const DomainBoundary& boundary,
                                      const ShellGeometry& shells, const geometry::ShellBand* band,
                                      ProjectionStats& stats) {
  for (int a = 0; a < 3; ++a) {
    auto& flags = m_neumann[a];
    std::fill(flags.begin(), flags.end(), 0);
    boundary.for_each_closed_face(m_grid, a, [&](std::int64_t f, const FaceCondition&) {
      flags[f] = 1;  // wall and inflow faces of the domain, source faces
    });
    if (band == nullptr || shells.empty()) continue;
    // Fig. 5: a ray between the two cell centres that meets a shell closes the face (the
    // rays the coupling solve cast, when it ran on these shells).
    const auto& hits = shells.cell_face_hits(*band)[a];
    const std::int64_t closed = static_cast<std::int64_t>(hits.size());
    auto& u = mac.face_velocity(a);
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < closed; ++s) {
      const auto& [f, hit] = hits[s];
      flags[f] = 2;
      u[f] = shells.velocity_at(hit)[a];  // §4.3: the (effective) object velocity
    }
    stats.shell_neumann_faces += closed;
  }
}

void PressureProjection::correct_compatibility(MacGrid& mac, ProjectionStats& stats) {
  const int regions = static_cast<int>(m_regions.enclosed.size());
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
    if (m_regions.enclosed[r] != 0 && m_regions.sealed[r] == 0) order.push_back(r);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) {
    return m_regions.start[x + 1] - m_regions.start[x] <
           m_regions.start[y + 1] - m_regions.start[y];
  });
  for (const int r : order) {
    double net = 0.0;
    faces.clear();
    std::vector<BoundaryFace> shared;  // faces shared with corrected enclosed regions
    for (std::int64_t s = m_regions.start[r]; s < m_regions.start[r + 1]; ++s) {
      const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, m_regions.cells[s]);
      net += mac.outward_flux(c);
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          const std::int64_t f = face_of(c, a, side);
          if (m_neumann[a][f] == 0) continue;
          const std::int64_t nb = neighbour(c, a, side);
          if (nb >= 0 && m_regions.region[nb] == r) continue;  // inside the region: cancels
          const BoundaryFace bf{a, f, side == 1 ? 1.0 : -1.0};
          if (nb >= 0 && m_regions.region[nb] >= 0 && corrected[m_regions.region[nb]] != 0) {
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

double free_surface_inverse_theta(const FreeSurface& surface, std::int64_t liquid,
                                  std::int64_t air) {
  if (!surface.ghost_fluid) return 1.0;
  const double phi_l = surface.cell_phi[liquid];
  const double phi_a = surface.cell_phi[air];
  const double theta = phi_l / (phi_l - phi_a);  // in [0, 1]: φ_l <= 0 < φ_a
  return 1.0 / std::clamp(theta, FreeSurface::kMinTheta, 1.0);
}

double PressureProjection::inverse_theta(std::int64_t liquid, std::int64_t air) const {
  return free_surface_inverse_theta(*m_surface, liquid, air);
}

void PressureProjection::find_solve_box() {
  // Water: the unknowns are the liquid cells, so the solve runs on their bounding box
  // (cells outside are air, p' = 0); smoke: the whole grid.
  const Eigen::Vector3i n = m_grid.cells();
  Eigen::Vector3i lo = Eigen::Vector3i::Zero(), hi = n;
  if (m_surface != nullptr) {
    lo = n;
    hi = Eigen::Vector3i::Zero();
    for (int r = 0; r < m_regions.count(); ++r)
      for (std::int64_t s = m_regions.start[r]; s < m_regions.start[r + 1]; ++s) {
        const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, m_regions.cells[s]);
        lo = lo.cwiseMin(c);
        hi = hi.cwiseMax(c + Eigen::Vector3i::Ones());
      }
    if ((hi.array() <= lo.array()).any()) {  // no liquid: a one-cell box of air
      lo.setZero();
      hi.setOnes();
    }
  }
  m_box_lo = lo;
  const Eigen::Vector3i size = hi - lo;
  if (m_laplacian.cells() != size) m_laplacian = linear::GridLaplacian(size);
  if (size == n) {  // unknown u is cell u
    m_box_cells.clear();
    m_box_cells.shrink_to_fit();
    return;
  }
  m_box_cells.resize(size.prod());
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < size.z(); ++k)
    for (int j = 0; j < size.y(); ++j)
      for (int i = 0; i < size.x(); ++i)
        m_box_cells[i + std::int64_t(size.x()) * (j + std::int64_t(size.y()) * k)] =
            m_grid.index(Location::Cell, Eigen::Vector3i(i, j, k) + lo);
}

void PressureProjection::build_operator() {
  find_solve_box();
  const Eigen::Vector3i n = m_grid.cells();
  const Eigen::Vector3i box = m_laplacian.cells();
  // Face weights: 1 where the face is open (interior or Dirichlet domain face), 0 where
  // it is Neumann (shell, wall, inflow) or touches an air cell — the MAC face layout,
  // restricted to the box (a box face inside the grid has air beyond it: weight 0).
  for (int a = 0; a < 3; ++a) {
    const auto& flags = m_neumann[a];
    auto& w = m_laplacian.weights(a);
    const Eigen::Vector3i faces = m_laplacian.face_counts(a);
#pragma omp parallel for collapse(2) schedule(static)
    for (int k = 0; k < faces.z(); ++k)
      for (int j = 0; j < faces.y(); ++j)
        for (int i = 0; i < faces.x(); ++i) {
          Eigen::Vector3i c = Eigen::Vector3i(i, j, k) + m_box_lo;  // the face's + cell
          const std::int64_t local =
              i + std::int64_t(faces.x()) * (j + std::int64_t(faces.y()) * k);
          double weight = flags[m_grid.index(face_location(a), c)] != 0 ? 0.0 : 1.0;
          if (weight != 0.0 && m_surface != nullptr) {
            const bool plus_air = c[a] < n[a] && air(m_grid.index(Location::Cell, c));
            c[a] -= 1;
            const bool minus_air = c[a] >= 0 && air(m_grid.index(Location::Cell, c));
            if (plus_air || minus_air) weight = 0.0;
          }
          w[local] = weight;
        }
    m_apertures.scale_weights(a, m_grid, m_box_lo, faces, w);
  }
  const auto unknown_of = [&](std::int64_t cell) {
    const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, cell) - m_box_lo;
    return static_cast<int>(c.x() + box.x() * (c.y() + box.y() * std::int64_t(c.z())));
  };
  auto& dirichlet = m_laplacian.dirichlet();
  if (m_surface == nullptr) {
    dirichlet.clear();
  } else {
    // §4.3 air cells: a liquid cell's open face to an air cell becomes its Dirichlet
    // conductance 1/θ (ghost fluid).
    const std::int64_t unknowns = m_laplacian.size();
    dirichlet.assign(unknowns, 0.0);
#pragma omp parallel for schedule(static)
    for (std::int64_t u = 0; u < unknowns; ++u) {
      const std::int64_t cell = box_cell(u);
      if (air(cell)) continue;
      const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, cell);
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          const std::int64_t nb = neighbour(c, a, side);
          if (nb < 0 || !air(nb) || m_neumann[a][face_of(c, a, side)] != 0) continue;
          dirichlet[u] += inverse_theta(cell, nb);
        }
    }
    // A liquid–air face near a shell conducts by its fraction.
    for (int a = 0; a < 3; ++a)
      for (const FaceApertures::Face& open : m_apertures.faces(a)) {
        if (air(open.plus) == air(open.minus)) continue;
        const bool plus_liquid = !air(open.plus);
        const std::int64_t liquid = plus_liquid ? open.plus : open.minus;
        const std::int64_t other = plus_liquid ? open.minus : open.plus;
        dirichlet[unknown_of(liquid)] += (open.fraction - 1.0) * inverse_theta(liquid, other);
      }
  }
  // Enclosed regions, numbered 0.. in region order: their constants are the null space.
  m_enclosed_count = m_regions.enclosed_count();
  m_first_enclosed_cell.clear();
  for (int r = 0; r < m_regions.count(); ++r)
    if (m_regions.enclosed[r] != 0)
      m_first_enclosed_cell.push_back(unknown_of(m_regions.cells[m_regions.start[r]]));
  m_null_space = m_regions.null_space(m_box_cells);  // empty without a singular region

  if (m_settings.solver == PressureSolver::Pcg &&
      m_settings.preconditioner == PressurePreconditioner::Multigrid) {
    m_multigrid.compute(m_laplacian);
  } else {
    m_matrix = m_laplacian.to_sparse();  // rows filled directly, no triplets
    if (m_settings.solver == PressureSolver::Cholmod) {
      for (const int c : m_first_enclosed_cell)
        m_matrix.coeffRef(c, c) += 1.0;  // fixes the constant; exact for a consistent b
      if (m_surface != nullptr)          // air cells: an identity row, p' = 0 for b = 0
        for (int u = 0; u < m_laplacian.size(); ++u)
          if (air(box_cell(u))) m_matrix.coeffRef(u, u) += 1.0;
    }
  }
}

void PressureProjection::solve(const MacGrid& mac, double scale, ProjectionStats& stats) {
  const int n = m_laplacian.size();
  // On a whole-grid box the solve reads the fluxes into b and works on m_scaled in place;
  // on a sub-box (water) it gathers them.
  const bool whole = m_box_cells.empty();
  Eigen::VectorXd& b = m_b;
  Eigen::VectorXd& x = whole ? m_scaled : m_x;
  if (whole) {
    cell_fluxes(mac, b);
#pragma omp parallel for schedule(static)
    for (int u = 0; u < n; ++u) b[u] = air(u) ? 0.0 : -b[u];  // no unknown in the air
  } else {
    cell_fluxes(mac, m_flux);
    b.resize(n);
    x.resize(n);
#pragma omp parallel for schedule(static)
    for (int u = 0; u < n; ++u) {
      const std::int64_t cell = m_box_cells[u];
      b[u] = air(cell) ? 0.0 : -m_flux[cell];
      x[u] = m_scaled[cell];
    }
    m_scaled.setZero();
  }
  m_null_space.project(b);  // consistent to round-off after the correction
  if (b.lpNorm<Eigen::Infinity>() == 0.0) {
    m_scaled.setZero();
    return;
  }
  linear::SolveStats result;
  if (m_settings.solver == PressureSolver::Cholmod) {
    linear::CholmodSolver direct;
    direct.compute(m_matrix);
    result = direct.solve(b, x);
  } else {
    // |r|_2 <= tol |b|_2, and also |r|_inf <= |r|_2 <= tol · max|u*| (the divergence bound).
    const double tolerance =
        std::min(m_settings.tolerance, m_settings.tolerance * scale / b.norm());
    if (m_settings.preconditioner == PressurePreconditioner::Multigrid) {
      result =
          linear::preconditioned_cg(m_laplacian, m_multigrid, b, x, tolerance,
                                    m_settings.max_iterations, &m_null_space, m_scratch.pcg.get());
    } else {
      linear::PcgMic0Solver pcg;
      pcg.compute(m_matrix);
      result = pcg.solve(b, x, tolerance, m_settings.max_iterations);
    }
    result.converged = result.converged || result.relative_residual <= tolerance;
  }
  stats.iterations += result.iterations;
  stats.max_region_iterations = std::max(stats.max_region_iterations, result.iterations);
  stats.relative_residual = std::max(stats.relative_residual, result.relative_residual);
  stats.converged = stats.converged && result.converged;
  if (!whole)
    for (int u = 0; u < n; ++u) m_scaled[m_box_cells[u]] = x[u];
}

ProjectionStats PressureProjection::project(MacGrid& mac, double dt, const DomainBoundary& boundary,
                                            const ShellGeometry& shells,
                                            const geometry::ShellBand* band,
                                            const FreeSurface* surface) {
  ProjectionStats stats;
  m_surface = surface;
  if (surface != nullptr) {
    const std::int64_t cells = m_grid.size(Location::Cell);
    m_liquid.resize(cells);
    std::int64_t liquid = 0;
#pragma omp parallel for schedule(static) reduction(+ : liquid)
    for (std::int64_t c = 0; c < cells; ++c) {
      m_liquid[c] = surface->cell_phi[c] <= 0.0 ? 1 : 0;
      liquid += m_liquid[c];
    }
    stats.liquid_cells = liquid;
  }
  apply_boundary_velocities(mac, boundary);
  mark_neumann(mac, boundary, shells, band, stats);
  m_apertures.clear();
  // Water fills a cell a shell cuts on its side only (its volume is φ's): face fractions.
  if (surface != nullptr && band != nullptr && !shells.empty())
    m_apertures.gather(shells, *band, m_neumann);
  const bool interior_closed = stats.shell_neumann_faces > 0 || boundary.has_source_faces();
  update_fluid_regions(m_grid, m_neumann, boundary, m_regions, interior_closed,
                       surface != nullptr ? std::span<const std::uint8_t>(m_liquid)
                                          : std::span<const std::uint8_t>());
  const int regions = static_cast<int>(m_regions.enclosed.size());
  stats.regions = regions;
  for (const auto e : m_regions.enclosed) stats.enclosed_regions += e;
  correct_compatibility(mac, stats);
  build_operator();
  stats.solve_cells = m_laplacian.size();

  // Solve, update the faces, and measure; a PCG solve whose largest cell divergence is
  // still above tolerance × max|u| (its stopping test bounds the 2-norm against max|u*|)
  // is refined by projecting the remaining divergence (iterative refinement, warm start 0).
  Eigen::VectorXd total;  // the sum over the passes, from the second pass on
  double max_div = 0.0;
  double speed = 0.0;
  const int passes = m_settings.solver == PressureSolver::Pcg ? 3 : 1;
  for (int pass = 0; pass < passes; ++pass) {
    const double scale = std::max(mac.max_face_speed(), 1e-300);
    if (pass == 1) total = m_scaled;
    if (pass > 0) m_scaled.setZero();
    solve(mac, scale, stats);
    apply_pressure(mac);
    if (pass > 0) total += m_scaled;
    max_div = max_cell_divergence(mac);
    speed = mac.max_face_speed();
    if (max_div <= m_settings.tolerance * speed) break;
  }
  if (total.size() > 0) m_scaled.swap(total);
  stats.max_relative_divergence = speed > 0.0 ? max_div / speed : 0.0;
  const double to_pressure = m_grid.dx() / dt;
  auto& p = mac.pressure();
  const std::int64_t cells = static_cast<std::int64_t>(p.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < cells; ++i) p[i] = m_scaled[i] * to_pressure;
  m_surface = nullptr;
  return stats;
}

ProjectionStats PressureProjection::project_parts(MacGrid& mac, FragmentVelocities& fragments,
                                                  double dt, const DomainBoundary& boundary,
                                                  const ShellGeometry& shells,
                                                  const CellParts& parts,
                                                  const CutCellSystem::Liquid& water,
                                                  std::span<const Eigen::Vector3d> shell_flux) {
  ProjectionStats stats;
  apply_boundary_velocities(mac, boundary);
  m_apertures.clear();
  const std::int64_t cells = m_grid.size(Location::Cell);
  // What the extrapolation reads: the closed faces and the liquid slots.
  for (int a = 0; a < 3; ++a) {
    auto& flags = m_neumann[a];
    std::fill(flags.begin(), flags.end(), 0);
    boundary.for_each_closed_face(m_grid, a,
                                  [&](std::int64_t f, const FaceCondition&) { flags[f] = 1; });
    for (const FaceSplit& split : parts.split_faces(a)) {
      const auto list = parts.fragments_of(a, split);
      if (flags[split.face] != 0 ||
          std::any_of(list.begin(), list.end(),
                      [&](const FaceFragment& f) { return parts.joins_slots(f); }))
        continue;
      // §4.3: a face the shells close between the two centres moves with them.
      flags[split.face] = 2;
      ++stats.shell_neumann_faces;
      const Eigen::Vector3d x = m_grid.position(face_location(a), split.face);
      Eigen::Vector3d below = x, above = x;
      below[a] -= 0.5 * m_grid.dx();
      above[a] += 0.5 * m_grid.dx();
      mac.face_velocity(a)[split.face] = shells.object_velocity(below, above)[a];
    }
  }
  m_parts_system.build(m_grid, parts, boundary, water, shell_flux);
  m_regions.region.assign(cells, -1);
  std::int64_t liquid = 0;
  for (std::int64_t c = 0; c < cells; ++c)
    if (m_parts_system.liquid(static_cast<int>(c))) {
      m_regions.region[c] = 0;
      ++liquid;
    }
  stats.liquid_cells = liquid;
  stats.solve_cells = m_parts_system.laplacian().size();
  const linear::GridLaplacian& a = m_parts_system.laplacian();
  const linear::ConstantNullSpace null_space = linear::null_space_of(a);
  m_multigrid.compute(a);
  Eigen::VectorXd flux, b, x, total = Eigen::VectorXd::Zero(a.size());
  for (int pass = 0; pass < 3; ++pass) {
    m_parts_system.outward_flux(mac, fragments, flux);
    const double scale = std::max(mac.max_face_speed(), max_fragment_speed(fragments));
    if (pass > 0 && flux.lpNorm<Eigen::Infinity>() <= m_settings.tolerance * scale) break;
    b = -flux;
    null_space.project(b);
    if (b.lpNorm<Eigen::Infinity>() == 0.0) break;
    x.setZero(a.size());
    const double tolerance =
        std::min(m_settings.tolerance, m_settings.tolerance * std::max(scale, 1e-300) / b.norm());
    const linear::SolveStats result =
        linear::preconditioned_cg(a, m_multigrid, b, x, tolerance, m_settings.max_iterations,
                                  &null_space, m_scratch.pcg.get());
    stats.iterations += result.iterations;
    stats.max_region_iterations = std::max(stats.max_region_iterations, result.iterations);
    stats.relative_residual = std::max(stats.relative_residual, result.relative_residual);
    stats.converged =
        stats.converged && (result.converged || result.relative_residual <= tolerance);
    m_parts_system.apply_pressure(x, mac, fragments);
    total += x;
  }
  m_parts_system.outward_flux(mac, fragments, flux);
  const double speed = mac.max_face_speed();
  stats.max_relative_divergence = speed > 0.0 ? flux.lpNorm<Eigen::Infinity>() / speed : 0.0;
  const double to_pressure = m_grid.dx() / dt;
  auto& p = mac.pressure();
  for (std::int64_t c = 0; c < cells; ++c) {
    m_scaled[c] = total[c];
    p[c] = total[c] * to_pressure;
  }
  return stats;
}

void PressureProjection::cell_fluxes(const MacGrid& mac, Eigen::VectorXd& flux) const {
  // Σ over the six faces of u·n per cell (MacGrid::outward_flux), one grid row at a time.
  const Eigen::Vector3i n = m_grid.cells();
  const std::int64_t nx = n.x(), ny = n.y(), plane = nx * ny;
  const double* u = mac.face_velocity(0).data();
  const double* v = mac.face_velocity(1).data();
  const double* w = mac.face_velocity(2).data();
  flux.resize(m_grid.size(Location::Cell));
  double* out = flux.data();
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j) {
      const std::int64_t c = nx * (j + ny * k);
      const double* ux = u + (nx + 1) * (j + ny * k);
      const double* vy = v + nx * (j + (ny + 1) * k);
      const double* wz = w + c;
      for (std::int64_t i = 0; i < nx; ++i)
        out[c + i] = (ux[i + 1] - ux[i]) + (vy[i + nx] - vy[i]) + (wz[i + plane] - wz[i]);
    }
  m_apertures.adjust_fluxes(mac, flux);
  for (int r = 0; r < m_regions.count(); ++r)  // a source sets these cells' divergence
    if (m_regions.sealed[r] != 0) out[m_regions.cells[m_regions.start[r]]] = 0.0;
}

void PressureProjection::apply_pressure(MacGrid& mac) const {
  // u = u* − (p'_+ − p'_−) on every non-Neumann face (eq. (3)); p' = 0 outside open faces.
  const Eigen::Vector3i cells = m_grid.cells();
  const std::int64_t stride[3] = {1, cells.x(), std::int64_t(cells.x()) * cells.y()};
  const double* p = m_scaled.data();
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3i n = m_grid.counts(face_location(a));
    double* u = mac.face_velocity(a).data();
    const std::uint8_t* flags = m_neumann[a].data();
#pragma omp parallel for collapse(2) schedule(static)
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j) {
        const std::int64_t row = std::int64_t(n.x()) * (j + std::int64_t(n.y()) * k);
        for (int i = 0; i < n.x(); ++i) {
          const std::int64_t f = row + i;
          if (flags[f] != 0) continue;
          const int along = a == 0 ? i : (a == 1 ? j : k);
          // The cell on the face's + side has the face's coordinates.
          const std::int64_t hi = i + std::int64_t(cells.x()) * (j + std::int64_t(cells.y()) * k);
          const std::int64_t lo = hi - stride[a];
          if (m_surface != nullptr) {
            // §4.3 with air: liquid–air faces by the ghost fluid rule, air–air untouched.
            const bool plus_air = along == cells[a] || air(hi);
            const bool minus_air = along == 0 || air(lo);
            // The domain side of a boundary face counts as air (p = 0 beyond open sides).
            if (plus_air && minus_air) {
              continue;
            } else if (plus_air) {
              u[f] -= -p[lo] * (along == cells[a] ? 1.0 : inverse_theta(lo, hi));
              continue;
            } else if (minus_air) {
              u[f] -= p[hi] * (along == 0 ? 1.0 : inverse_theta(hi, lo));
              continue;
            }
          }
          const double p_plus = along < cells[a] ? p[hi] : 0.0;
          const double p_minus = along > 0 ? p[lo] : 0.0;
          u[f] -= p_plus - p_minus;
        }
      }
  }
}

double PressureProjection::max_cell_divergence(const MacGrid& mac) {
  Eigen::VectorXd& flux = m_box_cells.empty() ? m_b : m_flux;
  cell_fluxes(mac, flux);
  if (m_surface != nullptr)
    for (Eigen::Index c = 0; c < flux.size(); ++c)
      if (air(c)) flux[c] = 0.0;  // air is not constrained
  return flux.lpNorm<Eigen::Infinity>();
}

}  // namespace shellflow::grid_fluid
