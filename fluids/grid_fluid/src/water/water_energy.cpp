#include "shellflow/grid_fluid/water/water_energy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "shellflow/grid_fluid/mac/ordered_sum.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::grid_fluid {
namespace {

using grid::Location;

/// What one face contributes: its weight in K and which speed it counts towards.
struct FaceRole {
  double weight = 0.0;
  bool liquid = false;   ///< φ_face <= 0
  bool surface = false;  ///< liquid–air with geometric θ < ½
};

FaceRole face_role(const grid::UniformGrid& grid, const FreeSurface& surface, int axis,
                   std::int64_t face) {
  Eigen::Vector3i c = grid.coordinates(face_location(axis), face);
  const int along = c[axis];
  const bool has_hi = along < grid.cells()[axis];
  const std::int64_t hi = has_hi ? grid.index(Location::Cell, c) : -1;
  c[axis] -= 1;
  const std::int64_t lo = along > 0 ? grid.index(Location::Cell, c) : -1;
  FaceRole role;
  if (hi < 0 || lo < 0) {  // a domain side: its one cell
    const double phi = surface.cell_phi[hi < 0 ? lo : hi];
    role.liquid = phi <= 0.0;
    role.weight = role.liquid ? 0.5 : 0.0;
    return role;
  }
  const double phi_lo = surface.cell_phi[lo], phi_hi = surface.cell_phi[hi];
  const bool liquid_lo = phi_lo <= 0.0, liquid_hi = phi_hi <= 0.0;
  role.liquid = phi_lo + phi_hi <= 0.0;
  if (liquid_lo && liquid_hi) {
    role.weight = 1.0;
  } else if (liquid_lo || liquid_hi) {
    const std::int64_t l = liquid_lo ? lo : hi, a = liquid_lo ? hi : lo;
    role.weight = 1.0 / free_surface_inverse_theta(surface, l, a);
    role.surface = !role.liquid;  // θ = φ_l/(φ_l − φ_a) < ½ ⇔ φ_l + φ_a > 0
  }
  return role;
}

}  // namespace

double water_cell_fraction(double phi, double dx) {
  return std::clamp(0.5 - phi / dx, 0.0, 1.0);
}

WaterEnergy water_energy(const MacGrid& mac, const FreeSurface& surface, double density,
                         const Eigen::Vector3d& gravity, std::span<const double> fraction) {
  const grid::UniformGrid& grid = mac.grid();
  const std::int64_t cells = grid.size(Location::Cell);
  SHELLFLOW_ASSERT(static_cast<std::int64_t>(surface.cell_phi.size()) == cells);
  const double dx = grid.dx(), cell_volume = dx * dx * dx;
  WaterEnergy e;
  double weighted = 0.0;
  for (int a = 0; a < 3; ++a) {
    const auto& u = mac.face_velocity(a);
    const std::int64_t n = static_cast<std::int64_t>(u.size());
    weighted += ordered_sum(
        n, [&](std::int64_t f) { return face_role(grid, surface, a, f).weight * u[f] * u[f]; });
    double liquid = 0.0, thin = 0.0;
#pragma omp parallel for schedule(static) reduction(max : liquid, thin)
    for (std::int64_t f = 0; f < n; ++f) {
      const FaceRole role = face_role(grid, surface, a, f);
      if (role.liquid) liquid = std::max(liquid, std::abs(u[f]));
      if (role.surface) thin = std::max(thin, std::abs(u[f]));
    }
    e.max_liquid_speed = std::max(e.max_liquid_speed, liquid);
    e.max_surface_face_speed = std::max(e.max_surface_face_speed, thin);
  }
  e.kinetic = 0.5 * density * weighted * cell_volume;
  const auto water_in = [&](std::int64_t c) {
    return fraction.empty() ? water_cell_fraction(surface.cell_phi[c], dx) : fraction[c];
  };
  const double water = ordered_sum(cells, water_in);
  const double height = ordered_sum(cells, [&](std::int64_t c) {
    const double v = water_in(c);
    return v == 0.0 ? 0.0 : v * gravity.dot(grid.position(Location::Cell, c));
  });
  e.mass = density * water * cell_volume;
  e.potential = -density * height * cell_volume;
  return e;
}

}  // namespace shellflow::grid_fluid
