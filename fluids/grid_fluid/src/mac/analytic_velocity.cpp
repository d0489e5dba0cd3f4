#include "shellflow/grid_fluid/mac/analytic_velocity.hpp"

#include <cmath>
#include <numbers>

#include "shellflow/grid_fluid/mac/mac_grid.hpp"

namespace shellflow::grid_fluid {

using sdk::Schema;

Schema AnalyticVelocity::schema() {
  return Schema::variant("type", "a velocity field with a closed form (for known answers)")
      .option("taylor_green",
              Schema::object("the Taylor–Green vortex fitted to the domain box: u = U sin(πx̂) "
                             "cos(πŷ) cos(πẑ), v = −U (L_y/L_x) cos(πx̂) sin(πŷ) cos(πẑ), w = 0, "
                             "x̂ = (x − min)/L; divergence-free, no flow through the walls")
                  .field("amplitude", Schema::number(1.0).unit("m/s").doc("U"))
                  .field("gradient",
                         Schema::number(0.0).unit("m/s").doc(
                             "G: adds ∇φ, φ = G L_x/(2π) cos(2πx̂) cos(πŷ) cos(πẑ), a gradient "
                             "with no flow through the walls, which a projection must remove "
                             "(a manufactured projection test)")));
}

AnalyticVelocity::AnalyticVelocity(const nlohmann::json& params, const grid::UniformGrid& grid)
    : m_lo(grid.origin()),
      m_size(grid.upper() - grid.origin()),
      m_amplitude(params.at("amplitude").get<double>()),
      m_gradient(params.at("gradient").get<double>()) {}

Eigen::Vector3d AnalyticVelocity::velocity(const Eigen::Vector3d& x) const {
  constexpr double pi = std::numbers::pi;
  const Eigen::Vector3d s = (x - m_lo).cwiseQuotient(m_size);  // x̂, ŷ, ẑ in [0, 1]
  const double sx = std::sin(pi * s.x()), cx = std::cos(pi * s.x());
  const double sy = std::sin(pi * s.y()), cy = std::cos(pi * s.y());
  const double sz = std::sin(pi * s.z()), cz = std::cos(pi * s.z());
  const double U = m_amplitude, Lx = m_size.x(), Ly = m_size.y(), Lz = m_size.z();
  Eigen::Vector3d u(U * sx * cy * cz, -U * (Ly / Lx) * cx * sy * cz, 0.0);
  if (m_gradient != 0.0) {
    // ∇φ for φ = G L_x/(2π) cos(2πx̂) cos(πŷ) cos(πẑ).
    const double s2x = std::sin(2.0 * pi * s.x()), c2x = std::cos(2.0 * pi * s.x());
    const double G = m_gradient;
    u += Eigen::Vector3d(-G * s2x * cy * cz, -G * Lx / (2.0 * Ly) * c2x * sy * cz,
                         -G * Lx / (2.0 * Lz) * c2x * cy * sz);
  }
  return u;
}

void AnalyticVelocity::fill(MacGrid& mac) const {
  const grid::UniformGrid& g = mac.grid();
  for (int a = 0; a < 3; ++a) {
    auto& u = mac.face_velocity(a);
    const std::int64_t n = static_cast<std::int64_t>(u.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t f = 0; f < n; ++f) u[f] = velocity(g.position(face_location(a), f))[a];
  }
}

}  // namespace shellflow::grid_fluid
