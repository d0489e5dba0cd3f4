#include "shellflow/grid_fluid/pressure/cut_cell_system.hpp"

#include <algorithm>
#include <cmath>

#include "shellflow/grid_fluid/pressure/pressure_projection.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

namespace {
constexpr std::uint8_t kClosed = 1, kSplit = 2;

/// Calls f(face, minus, plus) for every face of family `axis`, with the cells on its two
/// sides (−1 beyond the domain).
template <class F>
void for_each_face(const grid::UniformGrid& grid, int axis, F&& f) {
  const std::int64_t count = grid.size(face_location(axis));
  for (std::int64_t face = 0; face < count; ++face) {
    const auto [minus, plus] = cells_beside(grid, axis, face);
    f(face, static_cast<int>(minus), static_cast<int>(plus));
  }
}
}  // namespace

void CutCellSystem::build(const grid::UniformGrid& grid, const CellParts& parts,
                          const DomainBoundary& boundary, const Liquid& water,
                          std::span<const Eigen::Vector3d> shell_flux) {
  m_grid = grid;
  m_parts = &parts;
  m_ghost_fluid = water.ghost_fluid;
  const Eigen::Vector3i n = grid.cells();
  const int cells = static_cast<int>(grid.size(Location::Cell));

  // Unknowns: the cells (their slots), then the extra parts in cell order.
  const auto all = parts.parts();
  m_part_unknown.assign(all.size(), -1);
  std::vector<int> extra_cell;
  m_phi.assign(water.cell_phi.begin(), water.cell_phi.end());
  for (size_t p = 0; p < all.size(); ++p) {
    if (all[p].slot) {  // its cell's unknown, φ as the water gives it (a film's slot)
      m_part_unknown[p] = static_cast<int>(all[p].cell);
      m_phi[all[p].cell] = water.part_phi[p];
      continue;
    }
    m_part_unknown[p] = cells + static_cast<int>(extra_cell.size());
    extra_cell.push_back(static_cast<int>(all[p].cell));
    m_phi.push_back(water.part_phi[p]);
  }

  if (m_laplacian.cells() != n) m_laplacian = linear::GridLaplacian(n);
  std::vector<linear::Link> links;
  auto& dirichlet = m_laplacian.dirichlet();
  dirichlet.assign(cells + extra_cell.size(), 0.0);
  for (int a = 0; a < 3; ++a) {
    const Location loc = face_location(a);
    auto& kind = m_face_kind[a];
    kind.assign(grid.size(loc), 0);
    boundary.for_each_closed_face(grid, a,
                                  [&](std::int64_t f, const FaceCondition&) { kind[f] = kClosed; });
    for (const FaceSplit& split : parts.split_faces(a))
      if (kind[split.face] == 0) kind[split.face] = kSplit;
    auto& w = m_laplacian.weights(a);
    for_each_face(grid, a, [&](std::int64_t f, int minus, int plus) {
      w[f] = 0.0f;
      if (kind[f] != 0) return;
      const bool plus_liquid = plus >= 0 && liquid(plus),
                 minus_liquid = minus >= 0 && liquid(minus);
      if (plus < 0 || minus < 0) {  // an open domain face: p = 0 beyond it
        if (plus_liquid || minus_liquid) w[f] = 1.0f;
      } else if (plus_liquid && minus_liquid) {
        w[f] = 1.0f;
      } else if (plus_liquid != minus_liquid) {
        const int wet = plus_liquid ? plus : minus, dry = plus_liquid ? minus : plus;
        dirichlet[wet] += inverse_theta(wet, dry);
      }
    });
    // Fragments: the slots' shared one is the structured face, the others links.
    for (const FaceSplit& split : parts.split_faces(a)) {
      if (kind[split.face] != kSplit) continue;
      for (const FaceFragment& fragment : parts.fragments_of(a, split)) {
        const auto [um, up] = fragment_unknowns(a, split.face, fragment);
        const bool lm = liquid(um), lp = liquid(up);
        if (lm && lp) {
          if (parts.joins_slots(fragment))
            w[split.face] += static_cast<float>(conductance(fragment));
          else
            links.push_back({um, up, static_cast<float>(conductance(fragment))});
        } else if (lm != lp) {
          const int wet = lm ? um : up, dry = lm ? up : um;
          dirichlet[wet] += conductance(fragment) * inverse_theta(wet, dry);
        }
      }
    }
  }
  m_laplacian.set_parts(std::move(extra_cell), links);
  m_shell_flux.clear();
  for (size_t p = 0; p < shell_flux.size(); ++p)
    if (const double q = shell_flux[p].sum(); q != 0.0)
      m_shell_flux.push_back({m_part_unknown[p], q});
}

std::pair<int, int> CutCellSystem::fragment_unknowns(int axis, std::int64_t face,
                                                     const FaceFragment& fragment) const {
  const auto [minus_cell, plus_cell] = cells_beside(m_grid, axis, face);
  const int minus =
      fragment.minus >= 0 ? m_part_unknown[fragment.minus] : static_cast<int>(minus_cell);
  const int plus = fragment.plus >= 0 ? m_part_unknown[fragment.plus] : static_cast<int>(plus_cell);
  return {minus, plus};
}

double CutCellSystem::inverse_theta(int liquid, int air) const {
  if (!m_ghost_fluid) return 1.0;
  const double theta = m_phi[liquid] / (m_phi[liquid] - m_phi[air]);
  return 1.0 / std::clamp(theta, FreeSurface::kMinTheta, 1.0);
}

void CutCellSystem::outward_flux(const MacGrid& mac, const FragmentVelocities& fragments,
                                 Eigen::VectorXd& flux) const {
  flux.setZero(m_laplacian.size());
  for (int a = 0; a < 3; ++a) {
    const auto& u = mac.face_velocity(a);
    const auto& kind = m_face_kind[a];
    for_each_face(m_grid, a, [&](std::int64_t f, int minus, int plus) {
      if (kind[f] == kSplit) return;
      if (plus >= 0) flux[plus] -= u[f];
      if (minus >= 0) flux[minus] += u[f];
    });
    for (const FaceSplit& split : m_parts->split_faces(a)) {
      if (kind[split.face] != kSplit) continue;
      const auto list = m_parts->fragments_of(a, split);
      for (size_t k = 0; k < list.size(); ++k) {
        const auto [um, up] = fragment_unknowns(a, split.face, list[k]);
        const double q = conductance(list[k]) * fragments[a][split.first + k];
        flux[um] += q;
        flux[up] -= q;
      }
    }
  }
  for (const auto& [u, q] : m_shell_flux) flux[u] += q;
  for (int u = 0; u < m_laplacian.size(); ++u)
    if (!liquid(u)) flux[u] = 0.0;
}

void CutCellSystem::apply_pressure(const Eigen::VectorXd& scaled, MacGrid& mac,
                                   FragmentVelocities& fragments) const {
  // The change across a face or fragment from unknown `minus` to `plus` (−1: beyond the
  // domain, p = 0): both liquid, one liquid (ghost fluid; an open side at θ = 1), or none.
  const auto gradient = [&](int minus, int plus) {
    const bool lm = minus >= 0 && liquid(minus), lp = plus >= 0 && liquid(plus);
    if (lm && lp) return scaled[plus] - scaled[minus];
    if (lm) return -scaled[minus] * (plus < 0 ? 1.0 : inverse_theta(minus, plus));
    if (lp) return scaled[plus] * (minus < 0 ? 1.0 : inverse_theta(plus, minus));
    return 0.0;
  };
  for (int a = 0; a < 3; ++a) {
    auto& u = mac.face_velocity(a);
    const auto& kind = m_face_kind[a];
    for_each_face(m_grid, a, [&](std::int64_t f, int minus, int plus) {
      if (kind[f] == 0) u[f] -= gradient(minus, plus);
    });
    for (const FaceSplit& split : m_parts->split_faces(a)) {
      if (kind[split.face] != kSplit) continue;
      const auto list = m_parts->fragments_of(a, split);
      for (size_t k = 0; k < list.size(); ++k) {
        const auto [um, up] = fragment_unknowns(a, split.face, list[k]);
        double& v = fragments[a][split.first + k];
        v -= gradient(um, up);
        if (m_parts->joins_slots(list[k])) u[split.face] = v;
      }
    }
  }
}

}  // namespace shellflow::grid_fluid
