#include "shellflow/grid_fluid/pressure/coupling_pressure.hpp"

#include <omp.h>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>

#include "shellflow/geometry/gauss_jacobi_refill.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/pressure/rigid_face_areas.hpp"
#include "shellflow/linear/constant_null_space.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

CouplingPressure::CouplingPressure(const grid::UniformGrid& grid, CouplingSettings settings,
                                   SolveScratch scratch)
    : m_grid(grid),
      m_settings(settings),
      m_multigrid(linear::MultigridSettings{}, scratch.multigrid),
      m_scratch(std::move(scratch)) {
  if (!(settings.fluid_density > 0.0))
    throw Error("CouplingPressure: the fluid density must be positive");
  for (int a = 0; a < 3; ++a) m_closed[a].assign(m_grid.size(face_location(a)), 0);
  m_scaled.setZero(m_grid.size(Location::Cell));
  m_laplacian = linear::GridLaplacian(m_grid.cells());
}

void CouplingPressure::classify_faces(const DomainBoundary& boundary, const ShellGeometry& shells,
                                      const geometry::ShellBand& band, sdk::ShellSet set,
                                      CouplingStats& stats) {
  m_shell_faces.clear();
  // The rigid two-way shells: one body each in the solve.
  m_body_of_shell.assign(set.size(), -1);
  m_bodies.clear();
  for (size_t i = 0; i < set.size(); ++i) {
    if (!set[i].receives_fluid_forces || !set[i].rigid) continue;
    const sdk::RigidBody& r = *set[i].rigid;
    m_body_of_shell[i] = static_cast<int>(m_bodies.size());
    RigidShellFaces& body = m_bodies.emplace_back();
    body.inverse_mass.topLeftCorner<3, 3>() = r.inverse_mass;
    body.inverse_mass.bottomRightCorner<3, 3>() = r.inverse_inertia;
    body.centre_of_mass = r.centre_of_mass;
    body.acceleration = r.acceleration;
    const auto& T = *set[i].triangles;
    const auto& x = set[i].positions;
    const int count = set[i].triangle_count();
    body.triangle_area.resize(count);
    body.triangle_centre.resize(count);
    for (int t = 0; t < count; ++t) {
      const Eigen::Vector3d p0 = x.row(T(t, 0)).transpose();
      const Eigen::Vector3d p1 = x.row(T(t, 1)).transpose();
      const Eigen::Vector3d p2 = x.row(T(t, 2)).transpose();
      const Eigen::Vector3d area = 0.5 * (p1 - p0).cross(p2 - p0);
      const Eigen::Vector3d centre = (p0 + p1 + p2) / 3.0;
      body.triangle_area[t] = area.norm();
      body.triangle_centre[t] = centre;
    }
  }
  const double dx = m_grid.dx();
  for (int a = 0; a < 3; ++a) {
    auto& closed = m_closed[a];
    std::fill(closed.begin(), closed.end(), 0);
    boundary.for_each_closed_face(m_grid, a, [&](std::int64_t f, const FaceCondition&) {
      closed[f] = 1;  // walls, inflow and source faces: Neumann
    });
    // Fig. 5: the segment between the two cell centres meets a shell (cast once per
    // geometry, shared with the projection).
    const auto& hits = shells.cell_face_hits(band)[a];
    const std::int64_t m = static_cast<std::int64_t>(hits.size());
    const size_t first = m_shell_faces.size();
    m_shell_faces.resize(first + hits.size());
    bool bad_density = false;
#pragma omp parallel for schedule(static) reduction(|| : bad_density)
    for (std::int64_t s = 0; s < m; ++s) {
      const auto& [f, hit] = hits[s];
      const double velocity = shells.velocity_at(hit)[a];
      double beta = 0.0;  // a one-way shell: Neumann, it does not yield to the fluid
      const int body = m_body_of_shell[hit.shell];
      if (body < 0 && shells.receives_forces(hit.shell)) {
        const double sigma = shells.surface_density_at(hit);
        if (!(sigma > 0.0)) bad_density = true;
        beta = m_settings.fluid_density * dx / sigma;  // ρ / ρ_face with ρ_face = σ Δx²/Δx³
      }
      m_shell_faces[first + s] = {a, f, velocity, beta, hit.s, body, hit.triangle};
    }
    if (bad_density)
      throw Error(
          "grid_fluid coupling: a two-way shell has a triangle of zero or negative "
          "surface density; give every two-way shell a positive surface density");
    for (size_t k = first; k < m_shell_faces.size(); ++k) {
      const ShellFace& sf = m_shell_faces[k];
      // A rigid body's faces close for the region labelling only (solve()).
      if (!sf.two_way() || sf.body >= 0) closed[sf.face] = 1;
      if (!sf.two_way()) {
        ++stats.kinematic_faces;
      } else {
        ++stats.coupled_faces;
        if (sf.body >= 0) ++stats.rigid_faces;
      }
    }
  }
  if (!m_bodies.empty()) assign_rigid_face_areas(set);
}

void CouplingPressure::assign_rigid_face_areas(sdk::ShellSet set) {
  const double dx = m_grid.dx();
  if (m_surface == nullptr) {
    // Smoke: a face stands for Δx² across its axis at its centre and moves with the shell
    // there, as the projection's Neumann face will (§4.3). Faces standing for their pieces
    // (below) disagree with the projection on how the fluid moves wherever a face's pieces
    // are not Δx², and that pumped energy into a closed box of air (+55 %) where nothing
    // else loads the body.
    for (ShellFace& sf : m_shell_faces) {
      if (sf.body < 0) continue;
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(sf.axis);
      const Eigen::Vector3d r =
          m_grid.position(face_location(sf.axis),
                          m_grid.coordinates(face_location(sf.axis), sf.face)) -
          m_bodies[sf.body].centre_of_mass;
      sf.row << e, r.cross(e);
      sf.flux = sf.velocity;
    }
    return;
  }
  // Water: the hydrostatic load is what floats a hull, and it is exact only when each face
  // stands for the pieces of shell it samples (Archimedes, the righting moment at any heel;
  // rigid_face_areas.hpp).
  // Each body's cuts, in one pass over the faces.
  std::vector<std::vector<size_t>> faces(m_bodies.size());
  std::vector<std::vector<RigidFaceCut>> cuts(m_bodies.size());
  for (size_t k = 0; k < m_shell_faces.size(); ++k) {
    const ShellFace& sf = m_shell_faces[k];
    if (sf.body < 0) continue;
    RigidFaceCut& cut = cuts[sf.body].emplace_back();
    cut.axis = sf.axis;
    cut.face = m_grid.coordinates(face_location(sf.axis), sf.face);
    cut.crossing = m_grid.position(face_location(sf.axis), cut.face)[sf.axis] + (sf.s - 0.5) * dx;
    cut.triangle = sf.triangle;
    faces[sf.body].push_back(k);
  }
  for (size_t shell = 0; shell < set.size(); ++shell) {
    const int body = m_body_of_shell[shell];
    if (body < 0) continue;
    const auto pieces =
        rigid_face_pieces(m_grid, set[shell], m_bodies[body].centre_of_mass, cuts[body]);
    for (size_t i = 0; i < faces[body].size(); ++i) {
      ShellFace& sf = m_shell_faces[faces[body][i]];
      sf.row << pieces[i].vector_area, pieces[i].moment;
      sf.row /= dx * dx;
      sf.flux = pieces[i].flux / (dx * dx);
    }
  }
}

Eigen::VectorXd CouplingPressure::right_hand_side(const MacGrid& mac) const {
  const std::int64_t cells = m_grid.size(Location::Cell);
  Eigen::VectorXd b(cells);
#pragma omp parallel for schedule(static)
  for (std::int64_t cell = 0; cell < cells; ++cell)
    b[cell] = -mac.outward_flux(m_grid.coordinates(Location::Cell, cell));
  m_apertures.adjust_fluxes(mac, b, -1.0);
  // Shell faces carry the shell's velocity (§5.1), not u*; a rigid body's faces enter
  // through its jumps in solve() (−Kᵀ V*, rigid_shell_coupling.hpp).
  for (const ShellFace& sf : m_shell_faces) {
    const double velocity = sf.body >= 0 ? 0.0 : sf.velocity;
    const double delta = velocity - mac.face_velocity(sf.axis)[sf.face];
    const auto [minus, plus] = cells_of(sf);
    b[plus] += delta;   // its min face: outward −u
    b[minus] -= delta;  // its max face: outward +u
  }
  return b;
}

void CouplingPressure::solve(Eigen::VectorXd& b, double dt, const DomainBoundary& boundary,
                             CouplingStats& stats) {
  // The β-weighted cell Laplacian (linear::GridLaplacian: a face of weight w couples its
  // cells, or its cell to q = 0 outside an open domain face; w = 0 is Neumann, and a rigid
  // body's faces, which the body couples).
  for (int a = 0; a < 3; ++a) {
    auto& w = m_laplacian.weights(a);
    const auto& closed = m_closed[a];
    const std::int64_t faces = static_cast<std::int64_t>(w.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t f = 0; f < faces; ++f) w[f] = closed[f] != 0 ? 0.0 : 1.0;
  }
  for (const ShellFace& sf : m_shell_faces)
    if (sf.two_way()) m_laplacian.weights(sf.axis)[sf.face] = sf.body >= 0 ? 0.0 : sf.beta;
  for (int a = 0; a < 3; ++a)
    m_apertures.scale_weights(a, m_grid, Eigen::Vector3i::Zero(), m_laplacian.face_counts(a),
                              m_laplacian.weights(a));
  if (m_surface != nullptr) {
    add_free_surface(b);
    if (!m_bodies.empty()) drop_sealed_cells(b);
  }
  build_jumps();
  // −Kᵀ V*: the flux of the rigid faces without the fluid (their gravity over the step in).
  for (size_t k = 0; k < m_shell_faces.size(); ++k) {
    const ShellFace& sf = m_shell_faces[k];
    if (sf.body >= 0)
      m_jumps[k].scatter(sf.flux + dt * sf.row.head<3>().dot(m_bodies[sf.body].acceleration), b);
  }
  label_regions(boundary, stats);
  const linear::ConstantNullSpace null_space = m_regions.null_space();
  for (int r = 0; r < m_regions.count(); ++r) {
    if (m_regions.enclosed[r] == 0) continue;
    double mean = 0.0;
    for (std::int64_t k = m_regions.start[r]; k < m_regions.start[r + 1]; ++k)
      mean += b[m_regions.cells[k]];
    mean /= static_cast<double>(m_regions.size(r));
    for (std::int64_t k = m_regions.start[r]; k < m_regions.start[r + 1]; ++k)
      b[m_regions.cells[k]] -= mean;
  }

  m_multigrid.compute(m_laplacian);
  const double dx = m_grid.dx();
  const RigidShellOperator coupled(m_laplacian, m_bodies, m_settings.fluid_density * dx * dx * dx);
  const linear::LinearOperator& op =
      m_bodies.empty() ? static_cast<const linear::LinearOperator&>(m_laplacian) : coupled;
  const auto result = linear::preconditioned_cg(
      op, m_multigrid, b, m_scaled, m_settings.tolerance, m_settings.max_iterations,
      null_space.empty() ? nullptr : &null_space, m_scratch.pcg.get());
  stats.iterations = result.iterations;
  stats.relative_residual = result.relative_residual;
  stats.converged = result.converged;
}

void CouplingPressure::drop_sealed_cells(Eigen::VectorXd& b) {
  const auto& dirichlet = m_laplacian.dirichlet();
  for (const ShellFace& sf : m_shell_faces) {
    if (sf.body < 0) continue;
    Eigen::Vector3i c = m_grid.coordinates(face_location(sf.axis), sf.face);
    for (int side = 0; side < 2; ++side, c[sf.axis] -= 1) {
      const std::int64_t cell = m_grid.index(Location::Cell, c);
      if (air(cell) || dirichlet[cell] != 0.0) continue;
      bool linked = false;
      for (int a = 0; a < 3 && !linked; ++a) {
        Eigen::Vector3i f = c;
        for (int step = 0; step < 2 && !linked; ++step, f[a] += 1)
          linked = m_laplacian.weights(a)[m_grid.index(face_location(a), f)] != 0.0;
      }
      if (linked) continue;
      m_liquid[cell] = 0;
      b[cell] = 0.0;
      m_scaled[cell] = 0.0;
    }
  }
}

void CouplingPressure::label_regions(const DomainBoundary& boundary, const CouplingStats& stats) {
  // One-way shells, rigid bodies and sources close interior faces here (the faces of
  // weight β stay open).
  const bool interior_closed = stats.kinematic_faces > 0 || stats.rigid_faces > 0 ||
                               boundary.has_source_faces() || m_surface != nullptr;
  const auto liquid = m_surface != nullptr ? std::span<const std::uint8_t>(m_liquid)
                                           : std::span<const std::uint8_t>();
  // Kept while the closed faces stay the same (a moving cloth's faces are open here).
  update_fluid_regions(m_grid, m_closed, boundary, m_regions, interior_closed, liquid);
  if (stats.rigid_faces == 0) return;
  // An enclosed region whose constant no body feels (K 1_r = 0: the inside of a closed
  // rigid shell, or fluid around one in a closed box) is a null vector of the whole
  // operator. One a body does feel (fluid sealed under a piston or lid) is not: the body
  // joins it to the cells across, so the rigid faces open and the labelling is redone.
  const int count = m_regions.count();
  std::vector<BodyVector> felt(count, BodyVector::Zero());
  std::vector<double> scale(count, 0.0);
  for (const RigidShellFaces& body : m_bodies) {
    std::fill(felt.begin(), felt.end(), BodyVector::Zero());
    std::fill(scale.begin(), scale.end(), 0.0);
    for (size_t f = 0; f < body.jumps.size(); ++f) {
      const FaceJump& jump = body.jumps[f];
      for (int k = 0; k < jump.count; ++k) {
        const int r = m_regions.region[jump.cell[k]];
        if (r < 0 || m_regions.enclosed[r] == 0) continue;
        felt[r] -= jump.weight[k] * body.rows[f];
        scale[r] += std::abs(jump.weight[k]) * body.rows[f].norm();
      }
    }
    for (int r = 0; r < count; ++r) {
      if (felt[r].norm() <= 1e-9 * scale[r]) continue;
      for (const ShellFace& sf : m_shell_faces)
        if (sf.body >= 0) m_closed[sf.axis][sf.face] = 0;
      label_fluid_regions(m_grid, m_closed, boundary, m_regions, interior_closed, liquid);
      return;
    }
  }
}

void CouplingPressure::add_free_surface(Eigen::VectorXd& b) {
  const std::int64_t cells = m_grid.size(Location::Cell);
  const Eigen::Vector3i n = m_grid.cells();
  auto& across_shell = m_two_way_face;  // θ = 1 across these
  for (int a = 0; a < 3; ++a) across_shell[a].assign(m_laplacian.weights(a).size(), 0);
  for (const ShellFace& sf : m_shell_faces)
    if (sf.two_way()) across_shell[sf.axis][sf.face] = 1;
  auto& dirichlet = m_laplacian.dirichlet();
  dirichlet.assign(cells, 0.0);
  // A liquid cell's open face to an air cell becomes its Dirichlet conductance.
#pragma omp parallel for schedule(static)
  for (std::int64_t cell = 0; cell < cells; ++cell) {
    if (air(cell)) {
      b[cell] = 0.0;
      m_scaled[cell] = 0.0;  // the guess: an empty row keeps it, so p = 0 in the air
      continue;
    }
    const Eigen::Vector3i c = m_grid.coordinates(Location::Cell, cell);
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        Eigen::Vector3i nb = c;
        nb[a] += side == 0 ? -1 : 1;
        if (nb[a] < 0 || nb[a] >= n[a]) continue;
        const std::int64_t other = m_grid.index(Location::Cell, nb);
        if (!air(other)) continue;
        Eigen::Vector3i f = c;
        f[a] += side;
        const std::int64_t face = m_grid.index(face_location(a), f);
        const double w = m_laplacian.weights(a)[face];
        if (w == 0.0) continue;
        dirichlet[cell] += across_shell[a][face] != 0
                               ? w
                               : w * free_surface_inverse_theta(*m_surface, cell, other);
      }
  }
  // Faces touching air leave the operator (after the conductances read their weights).
  for (int a = 0; a < 3; ++a) {
    auto& w = m_laplacian.weights(a);
    const Eigen::Vector3i faces = m_grid.counts(face_location(a));
#pragma omp parallel for collapse(2) schedule(static)
    for (int k = 0; k < faces.z(); ++k)
      for (int j = 0; j < faces.y(); ++j)
        for (int i = 0; i < faces.x(); ++i) {
          Eigen::Vector3i c(i, j, k);
          const std::int64_t face = m_grid.index(face_location(a), c);
          if (w[face] == 0.0) continue;
          const bool plus_air = c[a] < n[a] && air(m_grid.index(Location::Cell, c));
          c[a] -= 1;
          const bool minus_air = c[a] >= 0 && air(m_grid.index(Location::Cell, c));
          if (plus_air || minus_air) w[face] = 0.0;
        }
  }
}

void CouplingPressure::add_side_at_shell(FaceJump& jump, std::int64_t cell, int axis, int step,
                                         double reach, double sign) const {
  if (air(cell)) return;
  Eigen::Vector3i c = m_grid.coordinates(Location::Cell, cell);
  Eigen::Vector3i f = c;  // the face between the cell and its neighbour away from the shell
  if (step > 0) f[axis] += 1;
  c[axis] += step;
  bool slope = c[axis] >= 0 && c[axis] < m_grid.cells()[axis];
  if (slope) {
    const std::int64_t face = m_grid.index(face_location(axis), f);
    slope = m_closed[axis][face] == 0 && m_two_way_face[axis][face] == 0;
  }
  if (!slope) {
    jump.add(cell, sign);
    return;
  }
  const std::int64_t neighbour = m_grid.index(Location::Cell, c);
  if (air(neighbour)) {  // p = 0 at the ghost point θΔx away (the projection's free surface)
    jump.add(cell, sign * (1.0 + reach * free_surface_inverse_theta(*m_surface, cell, neighbour)));
  } else {
    jump.add(cell, sign * (1.0 + reach));
    jump.add(neighbour, -sign * reach);
  }
}

std::pair<std::int64_t, std::int64_t> CouplingPressure::cells_of(const ShellFace& sf) const {
  Eigen::Vector3i ijk = m_grid.coordinates(face_location(sf.axis), sf.face);
  const std::int64_t plus = m_grid.index(Location::Cell, ijk);
  ijk[sf.axis] -= 1;
  return {m_grid.index(Location::Cell, ijk), plus};
}

bool CouplingPressure::water_at_two_way_faces() const {
  for (const ShellFace& sf : m_shell_faces) {
    if (!sf.two_way()) continue;
    const auto [minus, plus] = cells_of(sf);
    if (!air(minus) || !air(plus)) return true;
  }
  return false;
}

void CouplingPressure::build_jumps() {
  m_jumps.assign(m_shell_faces.size(), FaceJump{});
  for (size_t k = 0; k < m_shell_faces.size(); ++k) {
    const ShellFace& sf = m_shell_faces[k];
    if (!sf.two_way()) continue;
    const int a = sf.axis;
    const auto [minus, plus] = cells_of(sf);
    FaceJump& jump = m_jumps[k];
    if (m_surface == nullptr) {  // smoke: between the cell centres
      jump.add(plus, 1.0);
      jump.add(minus, -1.0);
    } else {
      add_side_at_shell(jump, plus, a, 1, 1.0 - sf.s, 1.0);
      add_side_at_shell(jump, minus, a, -1, sf.s, -1.0);
    }
    if (sf.body < 0) continue;
    RigidShellFaces& body = m_bodies[sf.body];
    body.jumps.push_back(jump);
    body.rows.push_back(sf.row);
  }
}

void CouplingPressure::jumps_to_nodes(double to_pressure, CouplingStats& stats) {
  const std::int64_t nodes = m_grid.size(Location::Node);
  for (int a = 0; a < 3; ++a)
    if (m_node_valid[a].size() != static_cast<size_t>(nodes)) m_node_valid[a].assign(nodes, 0);
  m_node_jump.resize(nodes);
  for (const std::int64_t i : m_node_jump.indices())
    for (int a = 0; a < 3; ++a) m_node_valid[a][i] = 0;
  m_node_jump.clear();
  // Each shell face's jump p₊ − p₋ goes to its four nodes (summed, then averaged).
  for (size_t k = 0; k < m_shell_faces.size(); ++k) {
    const ShellFace& sf = m_shell_faces[k];
    if (!sf.two_way()) continue;
    const int a = sf.axis;
    const Eigen::Vector3i ijk = m_grid.coordinates(face_location(a), sf.face);
    double jump = m_jumps[k].of(m_scaled) * to_pressure;
    if (m_surface != nullptr) {
      // Water with air across the shell pushes it and never pulls: the model has no
      // adhesion (§8), and p < 0 against air is the lagged scheme's suction when a light
      // shell outruns the water, which pulled a cloth curtain back into a jet until it blew up.
      const auto [minus, plus] = cells_of(sf);
      const bool plus_air = air(plus), minus_air = air(minus);
      if (minus_air && !plus_air) jump = std::max(jump, 0.0);
      if (plus_air && !minus_air) jump = std::min(jump, 0.0);
    }
    stats.max_pressure_jump = std::max(stats.max_pressure_jump, std::abs(jump));
    const int b = (a + 1) % 3;
    const int c = (a + 2) % 3;
    for (int db = 0; db < 2; ++db)
      for (int dc = 0; dc < 2; ++dc) {
        Eigen::Vector3i node = ijk;
        node[b] += db;
        node[c] += dc;
        const std::int64_t i = m_grid.index(Location::Node, node);
        m_node_jump.insert(i, Eigen::Vector3d::Zero())[a] += jump;
        m_node_valid[a][i] += 1;
      }
  }
  for (const std::int64_t i : m_node_jump.indices())
    for (int a = 0; a < 3; ++a)
      if (m_node_valid[a][i] > 1) {
        m_node_jump[i][a] /= m_node_valid[a][i];
        m_node_valid[a][i] = 1;
      }
}

void CouplingPressure::forces_on_triangles(sdk::ShellSet set,
                                           std::span<sdk::TriangleVectors> forces,
                                           CouplingStats& stats) {
  const double dx = m_grid.dx();
  const Eigen::Vector3i last = m_grid.counts(Location::Node).array() - 2;
  // The trilinear stencil of each two-way triangle's barycentre (its lower node and the
  // weights along each axis), once per triangle for steps 3 and 4; shells in set order.
  m_stencils.clear();
  for (const auto& s : set) {
    if (!s.receives_fluid_forces) continue;
    const auto& T = *s.triangles;
    const size_t first = m_stencils.size();
    const int count = s.triangle_count();
    m_stencils.resize(first + count);
#pragma omp parallel for schedule(static)
    for (int tri = 0; tri < count; ++tri) {
      const Eigen::Vector3d x =
          (s.positions.row(T(tri, 0)) + s.positions.row(T(tri, 1)) + s.positions.row(T(tri, 2)))
              .transpose() /
          3.0;
      const Eigen::Vector3d g = (x - m_grid.origin()) / dx;
      TriangleStencil& st = m_stencils[first + tri];
      for (int a = 0; a < 3; ++a) {
        st.lower[a] = std::clamp(static_cast<int>(std::floor(g[a])), 0, std::max(0, last[a]));
        st.t[a] = std::clamp(g[a] - st.lower[a], 0.0, 1.0);
      }
    }
  }

  // Step 3: spread the jumps to every node of the triangles' stencils.
  std::vector<std::int64_t> candidates;
  candidates.reserve(8 * m_stencils.size());
  for (const TriangleStencil& st : m_stencils)
    for (int corner = 0; corner < 8; ++corner)
      candidates.push_back(m_grid.index(Location::Node, st.lower + corner_step(corner)));
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (const std::int64_t i : candidates) m_node_jump.insert(i, Eigen::Vector3d::Zero());
  const geometry::GaussJacobiRefill refill(m_grid, Location::Node, m_settings.spread_layers);
  for (int a = 0; a < 3; ++a) {
    std::vector<std::int64_t> isolated;
    struct AxisJumps {  // one axis of the node jumps, as the refill's values
      grid::SparseSamples<Eigen::Vector3d>* jumps;
      int axis;
      double& operator[](std::int64_t i) const { return (*jumps)[i][axis]; }
    };
    // The jump is a property of the sheet, the same seen from either side: no rays.
    refill.run(
        AxisJumps{&m_node_jump, a}, std::span<std::uint8_t>(m_node_valid[a]),
        std::span<const std::int64_t>(candidates), [](std::int64_t, std::int64_t) { return true; },
        [&](std::int64_t from, std::int64_t to) {
          if (from == to) isolated.push_back(from);  // called serially for these
          return 0.0;
        });
    for (const std::int64_t i : isolated) m_node_valid[a][i] = 2;  // no data: ignored below
  }

  // Step 4: D at the barycentre, [p] = D·n/|n|₁ over the axes with data, F = −[p] A n.
  size_t offset = 0;  // of the shell's triangles in m_stencils
  for (size_t si = 0; si < set.size(); ++si) {
    const auto& s = set[si];
    if (!s.receives_fluid_forces) continue;
    auto& out = forces[si];
    const auto& T = *s.triangles;
    const int count = s.triangle_count();
    std::int64_t missing = 0;
#pragma omp parallel for schedule(static) reduction(+ : missing)
    for (int tri = 0; tri < count; ++tri) {
      const Eigen::Vector3d p0 = s.positions.row(T(tri, 0)).transpose();
      const Eigen::Vector3d area = 0.5 * (s.positions.row(T(tri, 1)).transpose() - p0)
                                             .cross(s.positions.row(T(tri, 2)).transpose() - p0);
      const double a_norm = area.norm();
      if (a_norm == 0.0) continue;
      const Eigen::Vector3d normal = area / a_norm;
      const Eigen::Vector3i& lower = m_stencils[offset + tri].lower;
      const Eigen::Vector3d& t = m_stencils[offset + tri].t;
      double along = 0.0;   // Σ n_a D_a over axes with data
      double weight = 0.0;  // Σ |n_a| over the same axes
      for (int a = 0; a < 3; ++a) {
        double sum = 0.0, w_sum = 0.0;
        for (int corner = 0; corner < 8; ++corner) {
          const Eigen::Vector3i d = corner_step(corner);
          const std::int64_t i = m_grid.index(Location::Node, lower + d);
          if (m_node_valid[a][i] != 1) continue;
          const double w = (d.x() ? t.x() : 1.0 - t.x()) * (d.y() ? t.y() : 1.0 - t.y()) *
                           (d.z() ? t.z() : 1.0 - t.z());
          sum += w * m_node_jump[i][a];
          w_sum += w;
        }
        if (w_sum <= 1e-12) continue;
        along += normal[a] * sum / w_sum;
        weight += std::abs(normal[a]);
      }
      if (weight < 1e-6) {
        ++missing;
        continue;
      }
      out.row(tri) = -(along / weight) * area.transpose();
    }
    if (const int body = m_body_of_shell[si]; body >= 0)
      match_wrench(m_bodies[body], m_body_wrench[body], out);
    stats.triangles_without_jump += missing;
    stats.total_force += out.colwise().sum().transpose();
    offset += count;
  }
}

void CouplingPressure::match_wrench(const RigidShellFaces& body, const BodyVector& wrench,
                                    sdk::TriangleVectors& out) {
  const auto& area = body.triangle_area;
  const auto& centre = body.triangle_centre;
  const int count = static_cast<int>(area.size());
  const Eigen::Vector3d& com = body.centre_of_mass;
  double total = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  BodyVector now = BodyVector::Zero();  // the wrench of steps 3–4
  for (int t = 0; t < count; ++t) {
    total += area[t];
    centroid += area[t] * centre[t];
    const Eigen::Vector3d f = out.row(t).transpose();
    now.head<3>() += f;
    now.tail<3>() += (centre[t] - com).cross(f);
  }
  if (!(total > 0.0)) return;
  centroid /= total;
  // δf_t = A_t (α + β × r_t), r_t from the area centroid: Σ δf = α A, and its torque about
  // the centre of mass is d × α A + I_A β (d the centroid's offset, I_A the area inertia).
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (int t = 0; t < count; ++t) {
    const Eigen::Vector3d r = centre[t] - centroid;
    inertia += area[t] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  const Eigen::Vector3d force = wrench.head<3>() - now.head<3>();
  const Eigen::Vector3d torque = wrench.tail<3>() - now.tail<3>() - (centroid - com).cross(force);
  const Eigen::Vector3d alpha = force / total;
  // A shell with no area moment about some axis (a segment) takes no torque about it.
  const Eigen::Vector3d beta = inertia.completeOrthogonalDecomposition().solve(torque);
  for (int t = 0; t < count; ++t)
    out.row(t) += area[t] * (alpha + beta.cross(centre[t] - centroid)).transpose();
}

CouplingStats CouplingPressure::compute(const MacGrid& mac, double dt,
                                        const DomainBoundary& boundary, const ShellGeometry& shells,
                                        const geometry::ShellBand& band, sdk::ShellSet set,
                                        std::span<sdk::TriangleVectors> forces,
                                        const FreeSurface* surface) {
  CouplingStats stats;
  if (forces.size() != set.size())
    throw Error("CouplingPressure: one force matrix per shell expected");
  m_surface = surface;
  if (surface != nullptr) {
    const std::int64_t cells = m_grid.size(Location::Cell);
    m_liquid.resize(cells);
#pragma omp parallel for schedule(static)
    for (std::int64_t c = 0; c < cells; ++c) m_liquid[c] = surface->cell_phi[c] <= 0.0 ? 1 : 0;
  } else {
    m_laplacian.dirichlet().clear();
  }
  classify_faces(boundary, shells, band, set, stats);
  m_apertures.clear();
  if (surface != nullptr) m_apertures.gather(shells, band, m_closed);
  if (surface != nullptr && !water_at_two_way_faces()) {
    // Skip the solve: with air (p = 0) on both sides of every two-way face, every jump is
    // zero, and so is every force (a curtain before the jet reaches it).
    for (size_t si = 0; si < set.size(); ++si)
      if (set[si].receives_fluid_forces) forces[si].setZero();
    m_body_wrench.assign(m_bodies.size(), BodyVector::Zero());
    m_surface = nullptr;
    return stats;
  }
  Eigen::VectorXd b = right_hand_side(mac);
  solve(b, dt, boundary, stats);
  // The rigid bodies' wrenches as the solve has them (rigid_shell_coupling.hpp).
  m_body_wrench.resize(m_bodies.size());
  const double dx = m_grid.dx();
  const Eigen::VectorXd& q = m_scaled;
  for (size_t i = 0; i < m_bodies.size(); ++i)
    m_body_wrench[i] = m_settings.fluid_density * dx * dx * dx / dt * m_bodies[i].impulse(q);
  jumps_to_nodes(m_settings.fluid_density * dx / dt, stats);
  forces_on_triangles(set, forces, stats);
  m_surface = nullptr;
  return stats;
}

}  // namespace shellflow::grid_fluid
