// Seconds per step of the grid_fluid smoke plume by phase (advect, project), without
// shells and with a moving 30K-triangle sheet crossing the plume, for both pressure
// preconditioners (multigrid, MIC(0)); PCG iterations per step in the counters (against
// grid size: 32^3, 64^3, 128^3); peak memory of a whole plume run per size, each in its
// own process (ru_maxrss only grows, so one process per size):
//   build-*/bin/bench_grid_fluid --benchmark_filter=Plume
//   build-*/bin/bench_grid_fluid --benchmark_filter=PeakMemory
//   build-*/bin/bench_grid_fluid --peak-memory=128[,sheet][,mic0]   (one measurement)
// The issue's targets (issue 4) on the 2-core machine: 128^3 step (advection + projection
// to a relative residual of 1e-5, double precision) < 1.5 s without shells, < 2.0 s with
// the sheet; peak memory < 1 GB at 128^3. The shells' geometry alone, Fig. 5's face rays
// against the cut cells' parts: --benchmark_filter=CellParts.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "bench_peak_memory.hpp"
#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/grid_fluid_solver.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/pressure/fluid_regions.hpp"
#include "shellflow/runtime/schema_validator.hpp"

namespace {

using namespace shellflow;

constexpr int kSheetNodes = 123;  // 2 (123 − 1)^2 = 29,768 triangles ≈ 30K

std::unique_ptr<grid_fluid::GridFluid> plume(int resolution, bool mic0) {
  nlohmann::json params = {
      {"resolution", resolution},
      {"boundary", {{"y_max", {{"type", "open"}}}}},
      {"pressure", {{"tolerance", 1e-5}, {"preconditioner", mic0 ? "mic0" : "multigrid"}}},
      {"smoke", {{"temperature_buoyancy", 0.01}, {"vorticity_confinement", 0.3}}},
      {"sources", nlohmann::json::array({{{"shape", "sphere"},
                                          {"center", {0.5, 0.15, 0.5}},
                                          {"radius", 0.1},
                                          {"temperature", 400.0},
                                          {"velocity", {0.0, 1.0, 0.0}}}})}};
  runtime::SchemaValidator validator(".");
  validator.validate(params, grid_fluid::GridFluid::schema().json(), "");
  if (!validator.issues().empty())
    throw std::runtime_error("plume params: " + validator.issues().front().json_path + ": " +
                             validator.issues().front().message);
  return std::make_unique<grid_fluid::GridFluid>(params, sdk::Context{});
}

/// A sheet of 2 (n−1)^2 triangles across the plume at height y = 0.6, moving along x.
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

struct PhaseTimes {
  double advect = 0.0, project = 0.0, iterations = 0.0;
  int steps = 0;
};

/// One plume step (advect, project) at time t; adds its phase times to `times`.
void step(grid_fluid::GridFluid& fluid, double t, double dt, bool with_sheet, PhaseTimes& times) {
  std::vector<sdk::ShellSurface> n, np1;
  std::vector<sdk::Positions> v;
  if (with_sheet) {
    n = {sheet(kSheetNodes, t)};
    np1 = {sheet(kSheetNodes, t + dt)};
    v = {np1[0].velocities};
  }
  const auto t0 = std::chrono::steady_clock::now();
  fluid.advect(t, dt, n, np1);
  const auto t1 = std::chrono::steady_clock::now();
  fluid.project(dt, np1, v);
  const auto t2 = std::chrono::steady_clock::now();
  times.advect += std::chrono::duration<double>(t1 - t0).count();
  times.project += std::chrono::duration<double>(t2 - t1).count();
  times.iterations += fluid.last_step().projection.iterations;
  ++times.steps;
}

constexpr int kWarmUpSteps = 5;  // the plume under way before timing

void run_plume(benchmark::State& state, bool with_sheet) {
  const int resolution = static_cast<int>(state.range(0));
  const bool mic0 = state.range(1) != 0;
  auto fluid = plume(resolution, mic0);
  const double dt = 0.5 / resolution;
  double t = 0.0;
  PhaseTimes warm_up;
  for (int s = 0; s < kWarmUpSteps; ++s, t += dt) step(*fluid, t, dt, with_sheet, warm_up);
  PhaseTimes times;
  for (auto _ : state) {
    step(*fluid, t, dt, with_sheet, times);
    t += dt;
  }
  state.SetLabel(mic0 ? "mic0" : "multigrid");
  state.counters["advect_s"] = times.advect / times.steps;
  state.counters["project_s"] = times.project / times.steps;
  state.counters["step_s"] = (times.advect + times.project) / times.steps;
  state.counters["pcg_iterations"] = times.iterations / times.steps;
  state.counters["longest_solve"] = fluid->last_step().projection.max_region_iterations;
  state.counters["regions"] = fluid->last_step().projection.regions;
  state.counters["shell_faces"] =
      static_cast<double>(fluid->last_step().projection.shell_neumann_faces);
}

void BM_PlumeNoShells(benchmark::State& state) {
  run_plume(state, false);
}
void BM_PlumeWithSheet(benchmark::State& state) {
  run_plume(state, true);
}
// Args: resolution, preconditioner (0: multigrid, 1: MIC(0)).
BENCHMARK(BM_PlumeNoShells)
    ->ArgsProduct({{32, 64, 128}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(BM_PlumeWithSheet)
    ->ArgsProduct({{32, 64, 128}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

/// The region labelling both pressure solves run each step (fluid_regions.hpp), at the
/// paper curtain's 210×140×140 cells: a wall across x with a 40-cell square hole in it (one
/// region through the hole) and, with water, the upper half of the cells air. Args:
/// water (0/1), threads.
void BM_LabelRegions(benchmark::State& state) {
  const Eigen::Vector3i n(210, 140, 140);
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / 140.0, n);
  std::array<std::vector<std::uint8_t>, 3> closed;
  closed[0].assign(grid.size(grid::Location::FaceX), 0);
  closed[1].assign(grid.size(grid::Location::FaceY), 0);
  closed[2].assign(grid.size(grid::Location::FaceZ), 0);
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      if (std::abs(j - 70) > 20 || std::abs(k - 70) > 20)
        closed[0][grid.index(grid::Location::FaceX, 105, j, k)] = 1;
  std::vector<std::uint8_t> liquid;
  if (state.range(0) != 0) {
    liquid.assign(grid.size(grid::Location::Cell), 1);
    for (std::int64_t c = 0; c < grid.size(grid::Location::Cell); ++c)
      if (grid.coordinates(grid::Location::Cell, c).y() >= n.y() / 2) liquid[c] = 0;
  }
  const int threads = omp_get_max_threads();
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const grid_fluid::DomainBoundary boundary;
  grid_fluid::FluidRegions regions;
  for (auto _ : state) {
    grid_fluid::label_fluid_regions(grid, closed, boundary, regions, true, liquid);
    benchmark::DoNotOptimize(regions.region.data());
  }
  omp_set_num_threads(threads);
  state.counters["regions"] = regions.count();
}
BENCHMARK(BM_LabelRegions)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond);

/// What the shells' geometry costs per step at 128^3 (cut cells, issue #52): the band, Fig. 5's
/// face rays (cell_face_hits, today's pass) and the cells' parts (CellParts: node edges, parts,
/// shares, fragments) for the 30K-triangle sheet across the domain, flat (one plane holds the
/// triangles near each cell: exact shares) or waved (y = 0.6 + 0.02 sin(2π x / 0.15): the shares
/// from lines split where they cross). Args: resolution, waved (0/1).
void BM_CellParts(benchmark::State& state) {
  const int resolution = static_cast<int>(state.range(0));
  const bool waved = state.range(1) != 0;
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), 1.0 / resolution,
                               Eigen::Vector3i::Constant(resolution));
  sdk::ShellSurface surface = sheet(kSheetNodes, 0.0);
  if (waved)
    for (Eigen::Index i = 0; i < surface.positions.rows(); ++i)
      surface.positions(i, 1) += 0.02 * std::sin(2.0 * M_PI * surface.positions(i, 0) / 0.15);
  const std::vector<sdk::ShellSurface> shells{surface};
  double band_s = 0.0, faces_s = 0.0, parts_s = 0.0;
  std::size_t parts = 0, splits = 0;
  geometry::ShellBand band(grid);
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    band.clear();
    band.add(geometry::TriangleMesh(shells.front()), 2.0 * grid.dx());
    const grid_fluid::ShellGeometry geometry(shells, 1e-3 * grid.dx());
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(geometry.cell_face_hits(band)[0].data());
    const auto t2 = std::chrono::steady_clock::now();
    const grid_fluid::CellParts cut(geometry, band);
    const auto t3 = std::chrono::steady_clock::now();
    band_s += std::chrono::duration<double>(t1 - t0).count();
    faces_s += std::chrono::duration<double>(t2 - t1).count();
    parts_s += std::chrono::duration<double>(t3 - t2).count();
    parts = cut.parts().size();
    splits = cut.split_faces(0).size() + cut.split_faces(1).size() + cut.split_faces(2).size();
  }
  const double runs = static_cast<double>(state.iterations());
  state.counters["band_and_bvh_s"] = band_s / runs;
  state.counters["face_rays_s"] = faces_s / runs;
  state.counters["cell_parts_s"] = parts_s / runs;
  state.counters["parts"] = static_cast<double>(parts);
  state.counters["split_faces"] = static_cast<double>(splits);
}
BENCHMARK(BM_CellParts)
    ->ArgsProduct({{64, 128}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

/// `--peak-memory=N[,sheet][,mic0]`: a plume run (warm-up + 3 steps) in this process, then
/// its peak resident set (getrusage ru_maxrss) printed as "peak_rss_kb <value>".
int measure_peak_memory(const std::string& spec) {
  const int resolution = std::stoi(spec);
  const bool with_sheet = spec.find("sheet") != std::string::npos;
  const bool mic0 = spec.find("mic0") != std::string::npos;
  auto fluid = plume(resolution, mic0);
  const double dt = 0.5 / resolution;
  PhaseTimes times;
  for (int s = 0; s < kWarmUpSteps + 3; ++s) step(*fluid, s * dt, dt, with_sheet, times);
  return bench::print_peak_rss();
}

/// Peak memory of a plume run at each size, each measured in a fresh child process.
void BM_PeakMemory(benchmark::State& state) {
  bench::measure_in_child(state,
                          std::to_string(state.range(0)) + (state.range(1) != 0 ? ",sheet" : ""));
}
BENCHMARK(BM_PeakMemory)->ArgsProduct({{64, 128}, {0, 1}})->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], "--peak-memory=", 14) == 0) return measure_peak_memory(argv[i] + 14);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
