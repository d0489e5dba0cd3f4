#include "shellflow/grid_fluid/mac/analytic_velocity.hpp"

#include <Eigen/Geometry>  // cross
#include <cmath>
#include <numbers>

#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

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
                             "(a manufactured projection test)")))
      .option("rigid_rotation",
              Schema::object("a rigid turn u = ω × (x − c), once per period about an axis "
                             "through c (Zalesak's slotted sphere: c = (50, 50, 50), axis z, "
                             "period 628 s in [0, 100]^3; Enright et al. 2002, §5.3)")
                  .field("center", Schema::vec3().unit("m").doc("a point c on the axis"))
                  .field("axis", Schema::vec3(0.0, 0.0, 1.0).doc(
                                     "direction of the axis (normalised; turns "
                                     "counter-clockwise about it)"))
                  .field("period", Schema::number().min(0.0, false).unit("s").doc(
                                       "time of one revolution")))
      .option("deformation",
              Schema::object("LeVeque's (1996) 3D deformation on the box mapped to the unit "
                             "cube, u_a = L_a û_a(x̂) cos(πt/T), û = 2 sin²(πx̂) sin(2πŷ) "
                             "sin(2πẑ), v̂ = −sin(2πx̂) sin²(πŷ) sin(2πẑ), ŵ = −sin(2πx̂) "
                             "sin(2πŷ) sin²(πẑ): divergence-free, reversed at T/2, every "
                             "point back at t = T (Enright et al. 2002, §5.4: T = 3 s, a "
                             "sphere of radius 0.15 at (0.35, 0.35, 0.35))")
                  .field("period", Schema::number(3.0).min(0.0, false).unit("s").doc(
                                       "T: the flow stops at T/2 and is undone by T")));
}

AnalyticVelocity::AnalyticVelocity(const nlohmann::json& params, const grid::UniformGrid& grid,
                                   const std::string& json_path)
    : m_lo(grid.origin()), m_size(grid.upper() - grid.origin()) {
  const std::string type = params.at("type").get<std::string>();
  if (type == "taylor_green") {
    m_kind = Kind::TaylorGreen;
    m_amplitude = params.at("amplitude").get<double>();
    m_gradient = params.at("gradient").get<double>();
  } else if (type == "rigid_rotation") {
    m_kind = Kind::RigidRotation;
    m_center = sdk::json_vec3(params, "center");
    const Eigen::Vector3d axis = sdk::json_vec3(params, "axis");
    if (!(axis.norm() > 0.0))
      throw ConfigError(json_path + "/axis", "the axis of rotation must not be zero");
    m_omega = (2.0 * std::numbers::pi / params.at("period").get<double>()) * axis.normalized();
  } else {
    m_kind = Kind::Deformation;
    m_period = params.at("period").get<double>();
  }
}

Eigen::Vector3d AnalyticVelocity::velocity(const Eigen::Vector3d& x, double t) const {
  constexpr double pi = std::numbers::pi;
  if (m_kind == Kind::RigidRotation) return m_omega.cross(x - m_center);
  const Eigen::Vector3d s = (x - m_lo).cwiseQuotient(m_size);  // x̂, ŷ, ẑ in [0, 1]
  const double sx = std::sin(pi * s.x()), cx = std::cos(pi * s.x());
  const double sy = std::sin(pi * s.y()), cy = std::cos(pi * s.y());
  const double sz = std::sin(pi * s.z()), cz = std::cos(pi * s.z());
  if (m_kind == Kind::Deformation) {
    // sin(2πx̂) = 2 sin(πx̂) cos(πx̂).
    const double s2x = 2.0 * sx * cx, s2y = 2.0 * sy * cy, s2z = 2.0 * sz * cz;
    const double time = std::cos(pi * t / m_period);
    return time * Eigen::Vector3d(2.0 * sx * sx * s2y * s2z, -s2x * sy * sy * s2z,
                                  -s2x * s2y * sz * sz)
                      .cwiseProduct(m_size);
  }
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

void AnalyticVelocity::fill(MacGrid& mac, double t) const {
  const grid::UniformGrid& g = mac.grid();
  for (int a = 0; a < 3; ++a) {
    auto& u = mac.face_velocity(a);
    const std::int64_t n = static_cast<std::int64_t>(u.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t f = 0; f < n; ++f) u[f] = velocity(g.position(face_location(a), f), t)[a];
  }
}

}  // namespace shellflow::grid_fluid
