// Preview rendering cost: a 480 x 360 frame of a 40 x 60 x 40 smoke plume with a plate
// (2 triangles) in front, and with a 20K-triangle sphere; the same frame of water (a pool
// and a falling ball, 41 x 61 x 41 nodes) with the plate.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "preview_fixture.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/preview_writer/preview_renderer.hpp"

namespace {

using namespace shellflow;

void add_plume(writer_testing::SyntheticFluid& fluid) {
  auto& d = fluid.add("density", sdk::FieldView::Location::Cell,
                      Eigen::Vector3d(-1.0, 0.0, -1.0).array() + 0.025, 0.05, {40, 60, 40}, 1);
  d.fill(0, [](const Eigen::Vector3d& x) {
    const double w = 0.15 + 0.25 * x.y();
    return 1.5 * std::exp(-(x.x() * x.x() + x.z() * x.z()) / (w * w)) *
           (0.5 + 0.5 * std::sin(6.0 * x.y()));
  });
}

preview_writer::PreviewSettings camera() {
  preview_writer::PreviewSettings s;
  s.camera_position = {0.6, 1.8, 3.5};
  s.look_at = {0.0, 1.3, 0.0};
  s.width = 480;
  s.height = 360;
  return s;
}

void BM_PreviewPlumeWithPlate(benchmark::State& state) {
  writer_testing::SyntheticFluid fluid;
  add_plume(fluid);
  std::vector<sdk::ShellSurface> shells{preview_writer::testing::square_shell(0.6, 0.35)};
  const preview_writer::PreviewRenderer renderer(camera());
  for (auto _ : state) benchmark::DoNotOptimize(renderer.render({0, 0.0, shells, &fluid}));
}
BENCHMARK(BM_PreviewPlumeWithPlate)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PreviewPlumeWithSphere(benchmark::State& state) {
  writer_testing::SyntheticFluid fluid;
  add_plume(fluid);
  const auto mesh = geometry::make_sphere(0.4, 5);  // 20480 triangles
  sdk::ShellSurface sphere;
  sphere.name = "ball/surface";
  sphere.positions = mesh.positions;
  sphere.positions.col(1).array() += 1.2;
  sphere.velocities = sdk::Positions::Zero(mesh.positions.rows(), 3);
  sphere.triangles = std::make_shared<const sdk::Triangles>(mesh.triangles);
  sphere.surface_density = Eigen::VectorXd::Ones(mesh.triangles.rows());
  const std::vector<sdk::ShellSurface> shells{sphere};
  const preview_writer::PreviewRenderer renderer(camera());
  for (auto _ : state) benchmark::DoNotOptimize(renderer.render({0, 0.0, shells, &fluid}));
  state.counters["triangles"] = static_cast<double>(mesh.triangles.rows());
}
BENCHMARK(BM_PreviewPlumeWithSphere)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Water: a pool below y = 0.5 and a ball of radius 0.4 at y = 1.5, on the plume's grid
/// as nodes, φ clamped to ±3 dx.
void add_pool_and_ball(writer_testing::SyntheticFluid& fluid) {
  const double dx = 0.05;
  auto& phi = fluid.add("phi", sdk::FieldView::Location::Node, Eigen::Vector3d(-1.0, 0.0, -1.0), dx,
                        {41, 61, 41}, 1);
  phi.fill(0, [&](const Eigen::Vector3d& x) {
    const double pool = x.y() - 0.5;
    const double ball = (x - Eigen::Vector3d(0.0, 1.5, 0.0)).norm() - 0.4;
    return std::clamp(std::min(pool, ball), -3.0 * dx, 3.0 * dx);
  });
}

void BM_PreviewWaterWithPlate(benchmark::State& state) {
  writer_testing::SyntheticFluid fluid;
  add_pool_and_ball(fluid);
  std::vector<sdk::ShellSurface> shells{preview_writer::testing::square_shell(0.6, 0.35)};
  const preview_writer::PreviewRenderer renderer(camera());
  for (auto _ : state) benchmark::DoNotOptimize(renderer.render({0, 0.0, shells, &fluid}));
}
BENCHMARK(BM_PreviewWaterWithPlate)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
