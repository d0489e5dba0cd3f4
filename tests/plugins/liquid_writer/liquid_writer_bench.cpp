// Liquid mesh cost: a sphere of water (R = 0.3) in an n^3 box of cells, its exact signed
// distance clamped to ±6Δx as grid_fluid clamps it, meshed with per-vertex velocity; with
// a plate through it (the clipping's cost) and with adaptivity 0.2.

#include <benchmark/benchmark.h>

#include <algorithm>

#include "mesh_checks.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/liquid_writer/liquid_mesher.hpp"

namespace {

using namespace shellflow;

void BM_MeshSphere(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool with_plate = state.range(1) != 0;
  const double dx = 1.0 / n;
  liquid_writer::testing::NodeGrid phi(Eigen::Vector3d::Zero(), dx, {n + 1, n + 1, n + 1}, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    return std::clamp((x - Eigen::Vector3d::Constant(0.5)).norm() - 0.3, -6.0 * dx, 6.0 * dx);
  });
  liquid_writer::testing::NodeGrid velocity(Eigen::Vector3d::Zero(), dx, {n + 1, n + 1, n + 1}, 3);
  velocity.fill(1, [](const Eigen::Vector3d& x) { return -x.y(); });
  const sdk::FieldView phi_view = phi.view("phi"), velocity_view = velocity.view("velocity");
  std::vector<sdk::ShellSurface> shells;
  if (with_plate) {
    auto grid = geometry::make_grid(1.2, 1.2, 33, 33, geometry::GridPattern::Alternating);
    sdk::ShellSurface plate;
    plate.positions.resize(grid.positions.rows(), 3);
    for (Eigen::Index i = 0; i < grid.positions.rows(); ++i)
      plate.positions.row(i) << 0.5 + dx / 3.0, 0.5 + grid.positions(i, 1),
          0.5 + grid.positions(i, 0);
    plate.triangles = std::make_shared<const sdk::Triangles>(grid.triangles);
    shells.push_back(plate);
  }
  liquid_writer::LiquidMeshOptions options;
  options.adaptivity = state.range(2) / 10.0;
  Eigen::Index vertices = 0;
  for (auto _ : state) {
    const auto mesh = liquid_writer::mesh_liquid(phi_view, &velocity_view, shells, options);
    vertices = mesh.positions.rows();
    benchmark::DoNotOptimize(mesh.triangles.data());
  }
  state.counters["vertices"] = static_cast<double>(vertices);
}
BENCHMARK(BM_MeshSphere)
    ->ArgsProduct({{64, 128}, {0, 1}, {0, 2}})
    ->ArgNames({"n", "plate", "adaptivity_x10"})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
