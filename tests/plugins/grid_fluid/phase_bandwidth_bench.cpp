// The 128^3 smoke plume's grid phases against the machine's memory bandwidth (issue 17,
// item 3). Each benchmark runs one phase of the step on an n^3 grid (no shells, every
// node and face live, as in the plume) and reports bytes_per_second from the phase's
// compulsory traffic: every array it must read and write, each counted once per pass
// (8 bytes a double, 4 a float, 1 a face flag), gathers and neighbour reads assumed to
// hit the cache, write-allocate fills not counted, as STREAM counts them. Compare with
// BM_StreamTriad (bench_memory) on as many threads: the ratio says how far a phase is
// from streaming its arrays once.
//   build/bin/bench_phase_bandwidth
//   build/bin/bench_memory
// The arrays per call (N nodes ≈ N cells ≈ N faces per family):
//   faces → nodes (§4.2)           read 3 face velocities, write 3 node velocities     6 × 8N
//   node advection (§4.1, smoke)   read 3 velocities + density + temperature, write 5 10 × 8N
//   vorticity confinement (smoke)  read u (3), write ω (3) and |ω|; read them back,
//                                  u read+write                                   17 × 8N
//   increments → faces (§4.2)      read u* (3) and u^n (3) at nodes, faces read+write 12 × 8N
//   Laplacian product + dot        read x, 3 face weights; write y                     5 × 8N
//   V-cycle (float, McAdams)       fine level only: in and out conversion (12 + 12),
//                                  8 half sweeps (x read+write 8, b 4, 1/diag 4, 3 open
//                                  flags 3), residual (x, b, 1/diag, flags, r: 19),
//                                  restriction 4, prolongation 8                  231 bytes/N
// The whole projection is timed too (divergence, the Laplacian's set-up, MG-PCG to 1e-5
// and the pressure update); its traffic is counted from its parts in the README table.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/face_node_transfer.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/semi_lagrangian_advector.hpp"
#include "shellflow/grid_fluid/pressure/pressure_projection.hpp"
#include "shellflow/grid_fluid/smoke/smoke_forces.hpp"
#include "shellflow/linear/grid_laplacian.hpp"
#include "shellflow/linear/multigrid_preconditioner.hpp"

namespace {

using namespace shellflow;
using grid::Location;
using grid_fluid::FaceNodeTransfer;
using grid_fluid::MacGrid;
using grid_fluid::NodeFields;
using grid_fluid::ShellGeometry;

constexpr double kAmbient = 300.0;

grid::UniformGrid cube(int n) {
  return grid::UniformGrid(Eigen::Vector3d::Zero(), 1.0 / n, Eigen::Vector3i(n, n, n));
}

/// A smooth swirling flow with a rising core (order 1 m/s), not divergence-free, on the faces.
void fill_faces(MacGrid& mac, double phase) {
  const grid::UniformGrid& g = mac.grid();
  for (int a = 0; a < 3; ++a) {
    auto& u = mac.face_velocity(a);
    const Location loc = grid_fluid::face_location(a);
#pragma omp parallel for schedule(static)
    for (std::int64_t f = 0; f < static_cast<std::int64_t>(u.size()); ++f) {
      const Eigen::Vector3d x = g.position(loc, f);
      u[f] = std::sin(6.0 * x[(a + 1) % 3] + phase) * std::cos(5.0 * x[(a + 2) % 3]) +
             (a == 1 ? 0.5 : 0.0);
    }
  }
}

std::int64_t face_count(const grid::UniformGrid& g) {
  std::int64_t n = 0;
  for (int a = 0; a < 3; ++a) n += g.size(grid_fluid::face_location(a));
  return n;
}

void BM_FacesToNodes(benchmark::State& state) {
  const grid::UniformGrid g = cube(static_cast<int>(state.range(0)));
  MacGrid mac(g);
  fill_faces(mac, 0.0);
  NodeFields nodes(g, kAmbient);
  const FaceNodeTransfer transfer(g);
  for (auto _ : state) {
    transfer.faces_to_nodes(mac, nodes, ShellGeometry(), nullptr);
    benchmark::DoNotOptimize(nodes.velocity(0).data());
  }
  const std::int64_t bytes = 8 * (face_count(g) + 3 * nodes.size());
  state.SetBytesProcessed(state.iterations() * bytes);
}

void BM_NodeAdvection(benchmark::State& state) {
  const grid::UniformGrid g = cube(static_cast<int>(state.range(0)));
  MacGrid mac(g);
  fill_faces(mac, 0.0);
  NodeFields in(g, kAmbient), out(g, kAmbient);
  FaceNodeTransfer(g).faces_to_nodes(mac, in, ShellGeometry(), nullptr);
  for (std::int64_t i = 0; i < in.size(); ++i) {
    in.density()[i] = std::sin(0.001 * static_cast<double>(i));
    in.temperature()[i] = kAmbient + in.density()[i];
  }
  const grid_fluid::SemiLagrangianAdvector advector(g, kAmbient);
  const double dt = 0.5 * g.dx();  // CFL about 1 at the flow's 1–2 m/s
  for (auto _ : state) {
    advector.advect(in, out, dt, ShellGeometry(), nullptr);
    benchmark::DoNotOptimize(out.velocity(0).data());
  }
  state.SetBytesProcessed(state.iterations() * 10 * 8 * in.size());
}

void BM_IncrementsToFaces(benchmark::State& state) {
  const grid::UniformGrid g = cube(static_cast<int>(state.range(0)));
  MacGrid mac(g);
  fill_faces(mac, 0.0);
  NodeFields u_star(g, kAmbient);
  FaceNodeTransfer transfer(g);
  transfer.faces_to_nodes(mac, u_star, ShellGeometry(), nullptr);
  std::array<std::vector<double>, 3> u_n;
  for (int a = 0; a < 3; ++a) {
    u_n[a] = u_star.velocity(a);
    for (double& v : u_n[a]) v *= 0.99;
  }
  const std::array<std::vector<std::uint8_t>, 3> no_faces;
  const grid_fluid::DomainBoundary walls;
  for (auto _ : state) {
    transfer.increments_to_faces(mac, u_star, u_n, {}, no_faces, ShellGeometry(), nullptr, walls);
    benchmark::DoNotOptimize(mac.face_velocity(0).data());
  }
  const std::int64_t bytes = 8 * (6 * u_star.size() + 2 * face_count(g));
  state.SetBytesProcessed(state.iterations() * bytes);
}

void BM_VorticityConfinement(benchmark::State& state) {
  const grid::UniformGrid g = cube(static_cast<int>(state.range(0)));
  MacGrid mac(g);
  fill_faces(mac, 0.0);
  NodeFields nodes(g, kAmbient);
  FaceNodeTransfer(g).faces_to_nodes(mac, nodes, ShellGeometry(), nullptr);
  grid_fluid::SmokeForces forces(g);
  for (auto _ : state)
    benchmark::DoNotOptimize(forces.add_vorticity_confinement(nodes, 1e-6, 0.3, ShellGeometry(), nullptr));
  state.SetBytesProcessed(state.iterations() * 17 * 8 * nodes.size());
}

linear::GridLaplacian unit_laplacian(int n) {
  linear::GridLaplacian a(Eigen::Vector3i(n, n, n));
  for (int axis = 0; axis < 3; ++axis) std::fill(a.weights(axis).begin(), a.weights(axis).end(), 1.0);
  return a;
}

void BM_LaplacianProduct(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const linear::GridLaplacian a = unit_laplacian(n);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(a.size(), 0.0, 1.0);
  Eigen::VectorXd y(a.size());
  for (auto _ : state) benchmark::DoNotOptimize(a.multiply_and_dot(x, y));
  std::int64_t weights = 0;
  for (int axis = 0; axis < 3; ++axis) weights += static_cast<std::int64_t>(a.weights(axis).size());
  state.SetBytesProcessed(state.iterations() * 8 * (2 * std::int64_t(a.size()) + weights));
}

void BM_VCycle(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const linear::GridLaplacian a = unit_laplacian(n);
  linear::MultigridPreconditioner mg;
  mg.compute(a);
  const Eigen::VectorXd r = Eigen::VectorXd::LinSpaced(a.size(), -1.0, 1.0);
  Eigen::VectorXd z;
  for (auto _ : state) {
    mg.apply(r, z);
    benchmark::DoNotOptimize(z.data());
  }
  state.SetBytesProcessed(state.iterations() * 231 * std::int64_t(a.size()));
}

void BM_Projection(benchmark::State& state) {
  const grid::UniformGrid g = cube(static_cast<int>(state.range(0)));
  MacGrid mac(g);
  grid_fluid::ProjectionSettings settings;
  settings.tolerance = 1e-5;
  grid_fluid::PressureProjection projection(g, settings);
  nlohmann::json open_top = {{"y_max", {{"type", "open"}}}};
  const grid_fluid::DomainBoundary boundary(open_top, "/boundary");
  double iterations = 0.0;
  double phase = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    fill_faces(mac, phase += 0.1);  // a new divergent field each time
    state.ResumeTiming();
    const auto stats = projection.project(mac, 0.01, boundary, ShellGeometry(), nullptr, nullptr);
    iterations += stats.iterations;
  }
  state.counters["pcg_iterations"] = iterations / static_cast<double>(state.iterations());
}

BENCHMARK(BM_FacesToNodes)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NodeAdvection)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_VorticityConfinement)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_IncrementsToFaces)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LaplacianProduct)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_VCycle)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Projection)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
