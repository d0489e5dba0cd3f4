// Thin-shell geometry kernel benchmarks (issue 3): segment visibility queries against a
// ~30K-triangle folded cloth, band labelling on a 128^3 grid, hierarchy refit, and grid
// swept-point invalidation. Run: build-<you>/bin/bench_geometry
//
// The query benchmarks run a batch of 2^20 segments with OpenMP on 1 and 2 threads
// (argument), timed on the wall clock (UseRealTime): items_per_second is the throughput
// of the whole machine. On a shared, busy machine wall time is inflated by the other
// load; the counter queries_per_cpu_s (queries over the process CPU time, all threads)
// is the per-core throughput, less sensitive to that load.
//
// Scene: unit box, 128^3 cells (dx = 1/128), wedge ε = 1e-3 dx (2011 PhysBAM default).
// The cloth is a (175 x 88)-node sheet folded over onto itself (two layers 2.5 dx apart,
// sharp fold at x = 0.9) with pleats of amplitude 4 dx: 30,276 triangles.

#include <benchmark/benchmark.h>
#include <omp.h>

#include <ctime>
#include <random>

#include "../unit/geometry/test_meshes.hpp"
#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/geometry/swept_point_invalidator.hpp"
#include "shellflow/geometry/wedge_caster.hpp"

namespace {

using namespace shellflow;
using namespace shellflow::geometry;

constexpr int kCells = 128;
constexpr double kDx = 1.0 / kCells;
constexpr double kEpsilon = 1e-3 * kDx;

test::Mesh folded_cloth() {
  test::Mesh m = test::make_folded_cloth(88, 2.5 * kDx);  // 4 * 87^2 = 30,276 triangles
  for (int i = 0; i < m.positions.rows(); ++i) {
    const double x = m.positions(i, 0), y = m.positions(i, 1);
    m.positions(i, 0) = 0.05 + 0.85 * x;
    m.positions(i, 1) = 0.05 + 0.9 * y;
    m.positions(i, 2) += 0.5 + 4.0 * kDx * std::sin(10.0 * y) * std::cos(3.0 * x);
  }
  return m;
}

const test::Mesh& cloth() {
  static const test::Mesh mesh = folded_cloth();
  return mesh;
}

struct Segments {
  std::vector<Eigen::Vector3d> a, b;
};

/// Segments between a point and a grid neighbour (length dx along an axis): `near`
/// places the start within 3 dx of a random cloth point (the band, where the fluid
/// casts rays); otherwise uniformly in the domain.
Segments make_segments(int n, bool near) {
  const TriangleMesh mesh(cloth().positions, cloth().triangles);
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> tri(0, mesh.triangle_count() - 1);
  std::uniform_int_distribution<int> axis(0, 5);
  Segments s;
  s.a.resize(n);
  s.b.resize(n);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d a(u(rng), u(rng), u(rng));
    if (near) {
      const TriangleCorners c = mesh.corners(tri(rng));
      double w1 = u(rng), w2 = u(rng);
      if (w1 + w2 > 1) w1 = 1 - w1, w2 = 1 - w2;
      a = c[0] + w1 * (c[1] - c[0]) + w2 * (c[2] - c[0]) +
          3.0 * kDx * Eigen::Vector3d(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);
    }
    const int d = axis(rng);
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    step[d % 3] = d < 3 ? kDx : -kDx;
    s.a[i] = a;
    s.b[i] = a + step;
  }
  return s;
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

void segment_queries(benchmark::State& state, bool near) {
  const TriangleMesh mesh(cloth().positions, cloth().triangles);
  const TriangleBvh bvh(mesh);
  const WedgeCaster caster(bvh, kEpsilon);
  const int n = 1 << 20;
  const Segments s = make_segments(n, near);
  const int threads = static_cast<int>(state.range(0));
  std::int64_t blocked = 0;
  double cpu = 0.0;
  for (auto _ : state) {
    const double cpu0 = process_cpu_seconds();
    std::int64_t count = 0;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : count)
    for (int i = 0; i < n; ++i) {
      count += caster.classify(s.a[i], s.b[i]) != Visibility::Visible;
    }
    cpu += process_cpu_seconds() - cpu0;
    blocked = count;
    benchmark::DoNotOptimize(count);
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["queries_per_cpu_s"] = double(state.iterations()) * n / cpu;
  state.counters["blocked_fraction"] = double(blocked) / n;
  state.counters["triangles"] = mesh.triangle_count();
}

void BM_SegmentQueriesNearCloth(benchmark::State& state) {
  segment_queries(state, true);
}
void BM_SegmentQueriesUniform(benchmark::State& state) {
  segment_queries(state, false);
}
BENCHMARK(BM_SegmentQueriesNearCloth)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SegmentQueriesUniform)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// WedgeCaster::first_hit (the semi-Lagrangian ray of §4.1, ε' = 2ε) on the near-cloth
/// segments, 1 and 2 threads.
void BM_FirstHitNearCloth(benchmark::State& state) {
  const TriangleMesh mesh(cloth().positions, cloth().triangles);
  const TriangleBvh bvh(mesh);
  const WedgeCaster caster(bvh, kEpsilon);
  const int n = 1 << 18;
  const Segments s = make_segments(n, true);
  const int threads = static_cast<int>(state.range(0));
  std::int64_t hits = 0;
  double cpu = 0.0;
  for (auto _ : state) {
    const double cpu0 = process_cpu_seconds();
    std::int64_t count = 0;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : count)
    for (int i = 0; i < n; ++i) {
      count += caster.first_hit(s.a[i], s.b[i], caster.semi_lagrangian_epsilon()).has_value();
    }
    cpu += process_cpu_seconds() - cpu0;
    hits = count;
    benchmark::DoNotOptimize(count);
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["queries_per_cpu_s"] = double(state.iterations()) * n / cpu;
  state.counters["hit_fraction"] = double(hits) / n;
}
BENCHMARK(BM_FirstHitNearCloth)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Clear + label nodes, cells and the three face families within dx of each triangle box.
void BM_BandLabelling128(benchmark::State& state) {
  const TriangleMesh mesh(cloth().positions, cloth().triangles);
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), kDx, Eigen::Vector3i::Constant(kCells));
  ShellBand band(grid);
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    band.clear();
    band.add(mesh, kDx);
    benchmark::DoNotOptimize(band.samples(grid::Location::Node).data());
  }
  std::int64_t total = 0;
  for (const auto location : grid::kAllLocations) total += band.samples(location).size();
  state.counters["band_samples"] = double(total);
  state.counters["node_fraction"] =
      double(band.samples(grid::Location::Node).size()) / grid.size(grid::Location::Node);
}
BENCHMARK(BM_BandLabelling128)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Refit after a small motion (alternating between two poses), rebuild if degraded.
void BM_Refit(benchmark::State& state) {
  const test::Mesh& m = cloth();
  sdk::Positions moved = m.positions;
  for (int i = 0; i < moved.rows(); ++i) moved(i, 2) += 0.5 * kDx * std::sin(20.0 * moved(i, 0));
  TriangleBvh bvh(TriangleMesh(m.positions, m.triangles));
  bool flip = false;
  int rebuilds = 0;
  for (auto _ : state) {
    flip = !flip;
    rebuilds += bvh.update(TriangleMesh(flip ? moved : m.positions, m.triangles));
  }
  state.counters["rebuilds"] = rebuilds;
  state.counters["sah_cost_ratio"] = bvh.bvh().cost() / bvh.bvh().build_cost();
}
BENCHMARK(BM_Refit)->Unit(benchmark::kMillisecond);

/// Full rebuild, for comparison with refit.
void BM_Build(benchmark::State& state) {
  const TriangleMesh mesh(cloth().positions, cloth().triangles);
  for (auto _ : state) {
    TriangleBvh bvh(mesh);
    benchmark::DoNotOptimize(bvh.bvh().nodes().data());
  }
}
BENCHMARK(BM_Build)->Unit(benchmark::kMillisecond);

/// §3 swept-node invalidation on 128^3 nodes for a step moving the cloth 0.5 dx.
void BM_SweptNodeInvalidation128(benchmark::State& state) {
  const test::Mesh& m = cloth();
  sdk::Positions moved = m.positions;
  moved.col(2).array() += 0.5 * kDx;
  const grid::UniformGrid grid(Eigen::Vector3d::Zero(), kDx, Eigen::Vector3i::Constant(kCells));
  const SweptPointInvalidator invalidator(grid, kEpsilon);
  std::vector<std::uint8_t> invalid(grid.size(grid::Location::Node), 0);
  std::vector<std::int64_t> list;
  omp_set_num_threads(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    for (const std::int64_t i : list) invalid[i] = 0;
    list.clear();
    invalidator.invalidate(grid::Location::Node, TriangleMesh(m.positions, m.triangles),
                           TriangleMesh(moved, m.triangles), invalid, list);
  }
  state.counters["invalid_nodes"] = double(list.size());
}
BENCHMARK(BM_SweptNodeInvalidation128)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
