#pragma once
// Helpers shared by the grid_fluid tests: a validated GridFluid from a JSON snippet, the
// water surface height on a node line, and shells built in the test (a flat plate).

#include <nlohmann/json.hpp>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"
#include "shellflow/grid_fluid/water/liquid.hpp"
#include "shellflow/runtime/schema_validator.hpp"

namespace shellflow::grid_fluid::test {

/// The params with the schema's defaults filled in (as the runtime passes them).
inline nlohmann::json validated(nlohmann::json params) {
  runtime::SchemaValidator validator(".");
  validator.validate(params, GridFluid::schema().json(), "");
  if (!validator.issues().empty())
    throw std::runtime_error("test params invalid at " + validator.issues().front().json_path +
                             ": " + validator.issues().front().message);
  return params;
}

inline std::unique_ptr<GridFluid> make_fluid(nlohmann::json params,
                                             Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81,
                                                                                       0)) {
  sdk::Context context;
  context.instance_name = "smoke";
  context.gravity = gravity;
  return std::make_unique<GridFluid>(validated(std::move(params)), context);
}

/// A square plate of side `size` centred at `center` with unit normal `normal`.
inline sdk::ShellSurface make_plate(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                                    double size, int nodes) {
  auto mesh = geometry::make_grid(size, size, nodes, nodes, geometry::GridPattern::Alternating);
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal);
  sdk::ShellSurface s;
  s.name = "plate";
  s.positions = mesh.positions;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i)
    s.positions.row(i) = (center + q * s.positions.row(i).transpose()).transpose();
  s.velocities = sdk::Positions::Zero(s.positions.rows(), 3);
  s.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  s.surface_density = Eigen::VectorXd::Ones(mesh.triangles.rows());
  return s;
}

/// Height of a water scene's surface on the vertical node line through (x, z): where φ
/// first crosses 0 going up, by linear interpolation between the nodes; −1 if it never does.
inline double surface_height(const GridFluid& f, double x, double z) {
  const auto& ls = f.liquid()->level_set();
  const double dx = f.grid().dx();
  double below = 0.0, phi_below = ls.sample({x, 0.0, z});
  for (double y = dx; y <= f.grid().upper().y() + 1e-12; y += dx) {
    const double phi = ls.sample({x, y, z});
    if (phi_below <= 0.0 && phi > 0.0) return below + dx * phi_below / (phi_below - phi);
    below = y;
    phi_below = phi;
  }
  return -1.0;
}

}  // namespace shellflow::grid_fluid::test
