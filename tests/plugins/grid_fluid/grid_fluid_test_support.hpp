#pragma once
// Helpers shared by the grid_fluid tests: a validated GridFluid from a JSON snippet, the
// water surface height on a node line, shells built in the test (a flat plate), a rigid
// shell that only translates along one axis (the smallest two-way solid), the value of one
// reported metric, and a run of static shells at the CFL step.

#include <gtest/gtest.h>
#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/pressure/cut_cell_system.hpp"
#include "shellflow/grid_fluid/water/liquid.hpp"
#include "shellflow/runtime/run_driver.hpp"
#include "shellflow/runtime/scene.hpp"
#include "shellflow/runtime/schema_validator.hpp"
#include "shellflow/sdk/metrics.hpp"
#include "shellflow/sdk/solid_solver.hpp"
#include "test_paths.hpp"

namespace shellflow::grid_fluid::test {

/// The metric `key` as the fluid reports it now (a test failure, and NaN, if it has none).
inline double reported(const sdk::FluidSolver& fluid, const std::string& key) {
  sdk::Metrics m;
  fluid.report(m);
  for (const auto& [k, v] : m.values())
    if (k == key) return v;
  ADD_FAILURE() << "no metric '" << key << "'";
  return NAN;
}

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

/// The scene file name validate_refusal() gives its scenes (it is never read or written).
inline constexpr const char* kRefusedScene = "refused_scene.json";

/// What `shellflow validate` says of a scene whose only plugin is a grid_fluid with the
/// parameters `fluid`, under gravity (0, −9.81, 0): the message a user reads, which names
/// the file and the JSON path from the scene's root ("/fluid/..."). Empty, and a test
/// failure, when the scene is accepted.
inline std::string validate_refusal(nlohmann::json fluid) {
  fluid["plugin"] = "grid_fluid";
  const nlohmann::json scene = {{"gravity", {0, -9.81, 0}}, {"fluid", std::move(fluid)}};
  try {
    // As validate does: load_scene's checks, then every plugin constructed.
    runtime::construct_plugins(
        runtime::parse_scene(scene.dump(), kRefusedScene, {shellflow::test_paths::plugin_dir()}));
  } catch (const SceneError& e) {
    return e.what();
  }
  ADD_FAILURE() << "the scene was accepted: " << scene.dump();
  return "";
}

/// Still shells in `grid`, their geometry (ε = 1e-3 Δx, the solver's) and the parts of the
/// cells they cut, found over a band grown by 2Δx (the solver's): the cut-cell tests' scene.
struct CutShells {
  CutShells(const grid::UniformGrid& grid, std::vector<sdk::ShellSurface> shells);
  std::vector<sdk::ShellSurface> shells;
  ShellGeometry geometry;
  geometry::ShellBand band;
  CellParts parts;
};

/// One projection on cut cells: solves A p' = −(the parts' outward flux) by MG-PCG to a
/// relative residual of 1e-13 (each enclosed component's constant projected out), applies
/// it to the faces and fragments, and returns p' per unknown.
Eigen::VectorXd project_on_parts(const CutCellSystem& system, MacGrid& mac,
                                 FragmentVelocities& fragments);

/// Uniform random velocities in [−amplitude, amplitude] on every interior face of `mac` and
/// every fragment (the domain's faces still), from seed `seed`.
void random_flow(MacGrid& mac, FragmentVelocities& fragments, double amplitude, unsigned seed);

/// A square plate of side `size` centred at `center` with unit normal `normal`.
/// (Defined in grid_fluid_test_support.cpp: Eigen's FromTwoVectors costs each file that
/// compiles it about 10 s, and 50 s with the sanitizers.)
sdk::ShellSurface make_plate(const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                             double size, int nodes);

/// A rigid shell that only translates along `axis`: M dv/dt = Σ F_axis + M g (symplectic
/// Euler), M = Σ σ A over its triangles, g the gravity along the axis. A held shell
/// receives the forces and records them (a force gauge) but does not move.
class TranslatingShell final : public sdk::SolidSolver {
 public:
  TranslatingShell(sdk::ShellSurface surface, int axis, double gravity, bool held)
      : m_surface(std::move(surface)), m_axis(axis), m_gravity(gravity), m_held(held) {
    m_surface.receives_fluid_forces = true;
    m_rest = m_surface.positions;
    const auto& T = *m_surface.triangles;
    for (int t = 0; t < m_surface.triangle_count(); ++t) {
      const Eigen::Vector3d a = m_rest.row(T(t, 0)), b = m_rest.row(T(t, 1)),
                            c = m_rest.row(T(t, 2));
      m_mass += m_surface.surface_density[t] * 0.5 * (b - a).cross(c - a).norm();
    }
    // One rigid body that moves along `axis` only (a held one: infinitely heavy).
    sdk::RigidBody body;
    if (!held) {
      body.inverse_mass(axis, axis) = 1.0 / m_mass;
      body.acceleration[axis] = gravity;
    }
    body.centre_of_mass = m_rest.colwise().mean().transpose();
    m_surface.rigid = body;
  }
  std::span<const sdk::ShellSurface> surfaces() const override { return {&m_surface, 1}; }
  void advance(double, double dt, std::span<const sdk::TriangleVectors> forces) override {
    m_forces = forces.empty() ? sdk::TriangleVectors() : forces[0];
    if (!m_held) {
      m_velocity += dt * (force()[m_axis] / m_mass + m_gravity);
      m_offset += dt * m_velocity;
    }
    m_surface.positions = m_rest;
    m_surface.positions.col(m_axis).array() += m_offset;
    m_surface.velocities.setZero();
    m_surface.velocities.col(m_axis).setConstant(m_velocity);
    m_surface.rigid->centre_of_mass[m_axis] = m_rest.col(m_axis).mean() + m_offset;
  }
  void save(sdk::StateWriter& out) const override {
    out.write(m_velocity);
    out.write(m_offset);
  }
  void restore(sdk::StateReader& in) override {
    m_velocity = in.read<double>();
    m_offset = in.read<double>();
    advance(0.0, 0.0, {});
  }
  void set_velocity(double v) {
    m_velocity = v;
    advance(0.0, 0.0, {});
  }
  double mass() const { return m_mass; }
  double offset() const { return m_offset; }
  double velocity() const { return m_velocity; }
  /// Σ of the triangle forces of the last advance() [N].
  Eigen::Vector3d force() const {
    return m_forces.rows() == 0 ? Eigen::Vector3d::Zero()
                                : Eigen::Vector3d(m_forces.colwise().sum().transpose());
  }
  /// Σ (c_t − point) × F_t of the last advance(), c_t the triangles' barycentres [N m].
  Eigen::Vector3d moment_about(const Eigen::Vector3d& point) const {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    const auto& T = *m_surface.triangles;
    for (int t = 0; t < m_forces.rows(); ++t) {
      const Eigen::Vector3d c =
          (m_surface.positions.row(T(t, 0)) + m_surface.positions.row(T(t, 1)) +
           m_surface.positions.row(T(t, 2)))
              .transpose() /
          3.0;
      m += (c - point).cross(Eigen::Vector3d(m_forces.row(t).transpose()));
    }
    return m;
  }

 private:
  sdk::ShellSurface m_surface;
  sdk::Positions m_rest;
  int m_axis;
  double m_gravity;
  bool m_held;
  sdk::TriangleVectors m_forces;
  double m_mass = 0.0;
  double m_velocity = 0.0;
  double m_offset = 0.0;
};

/// The water block `water` on one of the water cores the tests compare: "cells" (the level
/// set alone, /water/volume_fraction false) or "fraction" (with it, the default).
inline nlohmann::json water_core(const std::string& core, nlohmann::json water) {
  if (core != "cells" && core != "fraction" && core != "cut_cells")
    throw std::invalid_argument(
        "test::water_core: \"cells\", \"fraction\" or \"cut_cells\", not \"" + core + "\"");
  water["volume_fraction"] = core != "cells";
  if (core == "cut_cells") water["cut_cells"] = true;
  return water;
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

/// Steps `f` (no shells) from time t to `until` at the CFL step (0.9), calling each() after
/// every step (run_for starts at 0: an emitter's times need the run's own clock).
template <class Each>
void run_between(GridFluid& f, double t, double until, Each&& each) {
  while (t < until - 1e-12) {
    const double dt = std::min(f.stable_dt(0.9), until - t);
    f.advect(t, dt, {}, {});
    f.project(dt, {}, {});
    t += dt;
    each();
  }
}

/// Runs `f` with static `shells` for `duration` seconds from t = 0 at the CFL step (0.9);
/// returns the steps taken.
inline int run_for(GridFluid& f, double duration, sdk::ShellSet shells = {},
                   const std::vector<sdk::Positions>& v_eff = {}) {
  double t = 0.0;
  int steps = 0;
  while (t < duration - 1e-12) {
    const double dt = std::min(f.stable_dt(0.9), duration - t);
    f.advect(t, dt, shells, shells);
    f.project(dt, shells, v_eff);
    t += dt;
    ++steps;
  }
  return steps;
}

}  // namespace shellflow::grid_fluid::test
