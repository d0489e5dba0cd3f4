// Seconds per step of the grid_fluid smoke plume by phase (advect, project), without
// shells and with a moving sheet crossing the plume; PCG iterations in the counters.
//   build-*/bin/bench_grid_fluid --benchmark_filter=Plume
#include <benchmark/benchmark.h>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"
#include "shellflow/runtime/schema_validator.hpp"

namespace {

using namespace shellflow;

std::unique_ptr<grid_fluid::GridFluid> plume(int resolution) {
  nlohmann::json params = {
      {"resolution", resolution},
      {"boundary", {{"y_max", {{"type", "open"}}}}},
      {"pressure", {{"tolerance", 1e-5}}},
      {"smoke", {{"temperature_buoyancy", 0.01}, {"vorticity_confinement", 0.3}}},
      {"sources", nlohmann::json::array({{{"shape", "sphere"},
                                          {"center", {0.5, 0.15, 0.5}},
                                          {"radius", 0.1},
                                          {"temperature", 400.0},
                                          {"velocity", {0.0, 1.0, 0.0}}}})}};
  runtime::SchemaValidator validator(".");
  validator.validate(params, grid_fluid::GridFluid::schema().json(), "");
  return std::make_unique<grid_fluid::GridFluid>(params, sdk::Context{});
}

/// A sheet of 2 (n−1)^2 triangles across the plume at height y, moving along x.
sdk::ShellSurface sheet(int n, double t) {
  auto mesh = geometry::make_grid(0.6, 0.6, n, n, geometry::GridPattern::Alternating);
  sdk::ShellSurface s;
  s.positions = mesh.positions;
  for (Eigen::Index i = 0; i < s.positions.rows(); ++i) {
    const Eigen::Vector3d p = s.positions.row(i);
    s.positions.row(i) = Eigen::RowVector3d(0.5 + p.x() + 0.05 * t, 0.6, 0.5 + p.y());
  }
  s.velocities = sdk::Positions::Zero(s.positions.rows(), 3);
  s.velocities.col(0).setConstant(0.05);
  s.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  return s;
}

void run_plume(benchmark::State& state, bool with_sheet) {
  const int resolution = static_cast<int>(state.range(0));
  auto fluid = plume(resolution);
  const double dt = 0.5 / resolution;
  double t = 0.0;
  // Warm up so the plume is under way.
  for (int s = 0; s < 5; ++s) {
    fluid->advect(t, dt, {}, {});
    fluid->project(dt, {}, {});
    t += dt;
  }
  double advect = 0.0, project = 0.0, iterations = 0.0;
  int steps = 0;
  for (auto _ : state) {
    std::vector<sdk::ShellSurface> n, np1;
    std::vector<sdk::Positions> v;
    if (with_sheet) {
      n = {sheet(123, t)};  // 2·122² ≈ 30K triangles
      np1 = {sheet(123, t + dt)};
      v = {np1[0].velocities};
    }
    auto t0 = std::chrono::steady_clock::now();
    fluid->advect(t, dt, n, np1);
    auto t1 = std::chrono::steady_clock::now();
    fluid->project(dt, np1, v);
    auto t2 = std::chrono::steady_clock::now();
    advect += std::chrono::duration<double>(t1 - t0).count();
    project += std::chrono::duration<double>(t2 - t1).count();
    iterations += fluid->last_step().projection.iterations;
    ++steps;
    t += dt;
  }
  state.counters["advect_s"] = advect / steps;
  state.counters["project_s"] = project / steps;
  state.counters["pcg_iterations"] = iterations / steps;
}

void BM_PlumeNoShells(benchmark::State& state) {
  run_plume(state, false);
}
void BM_PlumeWithSheet(benchmark::State& state) {
  run_plume(state, true);
}
BENCHMARK(BM_PlumeNoShells)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(BM_PlumeWithSheet)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
