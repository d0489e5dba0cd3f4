// Thin-shell mass properties against analytic values (issue 5: "a test checks the inertia
// of a thin spherical shell and an open box against the analytic values").
#include "shellflow/bullet_rigid/shell_mass_properties.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::bullet_rigid {
namespace {

// Flat faces of a box mesh are represented exactly, so the triangle sums reproduce the
// analytic plate values up to round-off: ~100 terms of O(1) each, ε ≈ 1e-16 per term.
constexpr double kRoundOff = 1e-12;

/// Relative difference of two tensors in the Frobenius norm.
double relative_error(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return (a - b).norm() / b.norm();
}

TEST(ShellMassProperties, SquarePlateHasTheTextbookInertia) {
  // Thin square plate of side L and mass m in the x–y plane: I_xx = I_yy = m L²/12,
  // I_zz = m L²/6 (perpendicular-axis theorem).
  const double side = 0.8, density = 2.5;
  const auto mesh = geometry::make_grid(side, side, 5, 5, geometry::GridPattern::Alternating);
  const auto p = shell_mass_properties(mesh.positions, mesh.triangles, density);
  const double m = density * side * side;
  EXPECT_NEAR(p.area, side * side, kRoundOff);
  EXPECT_NEAR(p.mass, m, kRoundOff * m);
  EXPECT_LT(p.centre_of_mass.norm(), kRoundOff);
  const Eigen::Matrix3d expected =
      Eigen::Vector3d(m * side * side / 12, m * side * side / 12, m * side * side / 6).asDiagonal();
  EXPECT_LT(relative_error(p.inertia, expected), kRoundOff);
}

/// Second moments ∫x², ∫y², ∫z² (about the origin) of a uniform rectangular plate of mass
/// m centred at `centre` with side lengths `extent` along the axes (one extent is zero:
/// the plate's normal). For each axis: m (x0² + L²/12).
Eigen::Vector3d plate_second_moments(double m, const Eigen::Vector3d& centre,
                                     const Eigen::Vector3d& extent) {
  return m * (centre.array().square() + extent.array().square() / 12.0).matrix();
}

/// Inertia about the centre of mass of a box shell of sides (a, b, c), centred at the
/// origin, open towards +y when `open`, with surface density σ.
///
/// Derivation. The shell is five (open) or six (closed) rectangular plates:
///   bottom y = −b/2 (a × c), [top y = +b/2 (a × c)], walls x = ±a/2 (b × c),
///   walls z = ±c/2 (a × b); masses σ·area.
/// For a plate of mass m_p centred at x0 with extent L along an axis, ∫x² dm = m_p (x0² +
/// L²/12), so the second moments about the origin S = diag(∫x², ∫y², ∫z²) are plate sums;
/// the products ∫xy, ∫yz, ∫zx vanish by the mirror symmetries x → −x and z → −z (and
/// y → −y of the walls about their own centre). The centre of mass is (0, y_c, 0) with
/// y_c = m_bottom (−b/2) / M for the open box (0 for the closed one); the parallel-axis
/// shift gives S_yy' = S_yy − M y_c². Then I = tr(S') Id − S':
///   I_xx = S_yy' + S_zz,  I_yy = S_xx + S_zz,  I_zz = S_xx + S_yy'.
struct BoxShellExpected {
  double mass;
  double centre_y;
  Eigen::Matrix3d inertia;
};
BoxShellExpected box_shell_expected(double a, double b, double c, double sigma, bool open) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  double mass = 0.0, first_y = 0.0;
  auto plate = [&](const Eigen::Vector3d& centre, const Eigen::Vector3d& extent, double area) {
    const double m = sigma * area;
    s += plate_second_moments(m, centre, extent);
    mass += m;
    first_y += m * centre.y();
  };
  plate({0, -b / 2, 0}, {a, 0, c}, a * c);            // bottom
  if (!open) plate({0, b / 2, 0}, {a, 0, c}, a * c);  // top
  plate({-a / 2, 0, 0}, {0, b, c}, b * c);
  plate({a / 2, 0, 0}, {0, b, c}, b * c);
  plate({0, 0, -c / 2}, {a, b, 0}, a * b);
  plate({0, 0, c / 2}, {a, b, 0}, a * b);
  const double yc = first_y / mass;
  s.y() -= mass * yc * yc;
  BoxShellExpected e{mass, yc, Eigen::Matrix3d::Zero()};
  e.inertia.diagonal() << s.y() + s.z(), s.x() + s.z(), s.x() + s.y();
  return e;
}

TEST(ShellMassProperties, OpenBoxMatchesTheAnalyticPlateSum) {
  const double a = 0.6, b = 0.4, c = 0.3, sigma = 1.7;
  const auto mesh = geometry::make_open_box({a, b, c}, 3);
  const auto p = shell_mass_properties(mesh.positions, mesh.triangles, sigma);
  const auto e = box_shell_expected(a, b, c, sigma, /*open=*/true);
  EXPECT_NEAR(p.area, a * c + 2 * b * c + 2 * a * b, kRoundOff);
  EXPECT_NEAR(p.mass, e.mass, kRoundOff * e.mass);
  EXPECT_LT((p.centre_of_mass - Eigen::Vector3d(0, e.centre_y, 0)).norm(), kRoundOff);
  EXPECT_LT(relative_error(p.inertia, e.inertia), kRoundOff);
  // The open box is not a closed box: the missing lid moves the centre of mass down and
  // changes the tensor by far more than round-off (the test can tell them apart).
  const auto closed = box_shell_expected(a, b, c, sigma, /*open=*/false);
  EXPECT_GT(relative_error(p.inertia, closed.inertia), 1e-2);
}

TEST(ShellMassProperties, ClosedBoxMatchesTheAnalyticPlateSum) {
  const double a = 0.5, b = 0.2, c = 0.9, sigma = 0.3;
  const auto mesh = geometry::make_box({a, b, c}, 2);
  const auto p = shell_mass_properties(mesh.positions, mesh.triangles, sigma);
  const auto e = box_shell_expected(a, b, c, sigma, /*open=*/false);
  EXPECT_NEAR(p.mass, e.mass, kRoundOff * e.mass);
  EXPECT_LT(p.centre_of_mass.norm(), kRoundOff);
  EXPECT_LT(relative_error(p.inertia, e.inertia), kRoundOff);
}

TEST(ShellMassProperties, MovedShellKeepsItsInertiaRotatedAndItsMassCentreMoved) {
  // Rigid motion x ↦ R x + t: centre of mass ↦ R c + t, inertia ↦ R I Rᵀ.
  auto mesh = geometry::make_open_box({0.6, 0.4, 0.3}, 2);
  const auto before = shell_mass_properties(mesh.positions, mesh.triangles, 1.0);
  Eigen::Affine3d motion = Eigen::Affine3d::Identity();
  motion.translate(Eigen::Vector3d(3.0, -1.0, 2.0));
  motion.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  geometry::apply_transform(motion, mesh);
  const auto after = shell_mass_properties(mesh.positions, mesh.triangles, 1.0);
  const Eigen::Matrix3d r = motion.linear();
  // Coordinates of size 3 lose a few more bits in the parallel-axis shift: 1e-11.
  EXPECT_LT((after.centre_of_mass - motion * before.centre_of_mass).norm(), 1e-11);
  EXPECT_LT(relative_error(after.inertia, r * before.inertia * r.transpose()), 1e-11);
  // Principal decomposition reproduces the tensor and is a proper rotation.
  const Eigen::Matrix3d rebuilt = after.principal_axes * after.principal_moments.asDiagonal() *
                                  after.principal_axes.transpose();
  EXPECT_LT(relative_error(rebuilt, after.inertia), kRoundOff);
  EXPECT_NEAR(after.principal_axes.determinant(), 1.0, kRoundOff);
}

TEST(ShellMassProperties, SphericalShellConvergesToTwoThirdsMRSquared) {
  // Thin spherical shell: I = 2/3 m r² about any axis through its centre. The icosphere's
  // flat triangles sit inside the sphere, so the discrete value converges as O(h²): each
  // subdivision halves h and should divide the error by about 4.
  const double r = 0.7, sigma = 3.0;
  double previous_error = 0.0;
  for (int level = 2; level <= 5; ++level) {
    const auto mesh = geometry::make_sphere(r, level);
    const auto p = shell_mass_properties(mesh.positions, mesh.triangles, sigma);
    const double expected = 2.0 / 3.0 * p.mass * r * r;
    // Icosahedral symmetry makes the discrete tensor exactly isotropic (up to round-off).
    EXPECT_LT((p.inertia - p.inertia(0, 0) * Eigen::Matrix3d::Identity()).norm(),
              kRoundOff * p.inertia(0, 0));
    EXPECT_LT(p.centre_of_mass.norm(), kRoundOff * r);
    const double error = std::abs(p.inertia(0, 0) - expected) / expected;
    if (level > 2) {
      const double ratio = previous_error / error;
      EXPECT_GT(ratio, 3.5) << "level " << level;  // O(h²): ratio → 4
      EXPECT_LT(ratio, 4.5) << "level " << level;
    }
    previous_error = error;
  }
  // At level 5 (20480 triangles, h ≈ 0.03 r) the measured error is 3.6e-4 (5.8e-3 at
  // level 3); 5e-4 leaves room for round-off and rejects a solid-sphere formula (2/5 m r²,
  // 40% off) or a coarser mesh by far.
  EXPECT_LT(previous_error, 5e-4);
}

TEST(ShellMassProperties, MassIsSurfaceDensityTimesAreaPerTriangle) {
  // Per-triangle densities: two triangles of one square with densities 1 and 3 have mass
  // (1 + 3) · L²/2, and the centre of mass shifts towards the heavier triangle.
  sdk::Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  sdk::Triangles t(2, 3);
  t << 0, 1, 2, 0, 2, 3;
  Eigen::VectorXd rho(2);
  rho << 1.0, 3.0;
  const auto p = shell_mass_properties(x, t, rho);
  EXPECT_NEAR(p.mass, 2.0, kRoundOff);
  // Barycentres (2/3, 1/3) and (1/3, 2/3) weighted 0.5 and 1.5: (5/12, 7/12).
  EXPECT_LT((p.centre_of_mass - Eigen::Vector3d(5.0 / 12, 7.0 / 12, 0)).norm(), kRoundOff);
  EXPECT_THROW(shell_mass_properties(x, t, 0.0), Error);
}

}  // namespace
}  // namespace shellflow::bullet_rigid
