// The machine's memory bandwidth, the limit a grid phase that streams its arrays once per
// pass can reach (issue 17, item 3): McCalpin's STREAM triad a[i] = b[i] + s c[i] over three
// arrays of 2^25 doubles (256 MiB each, far beyond any cache), on 1 and on 2 threads.
// Bytes counted as STREAM counts them, 24 per element (two reads, one write; the write's
// cache-line fill, 8 more, is not counted), reported as bytes_per_second:
//   build/bin/bench_memory
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cstdint>
#include <vector>

namespace {

void BM_StreamTriad(benchmark::State& state) {
  const std::int64_t n = std::int64_t(1) << 25;
  const int threads = omp_get_max_threads();
  omp_set_num_threads(static_cast<int>(state.range(0)));
  std::vector<double> a(n), b(n), c(n);
  // First touch by the threads that will stream them (the pages' placement).
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    a[i] = 0.0;
    b[i] = 1.0;
    c[i] = 2.0;
  }
  const double s = 3.0;
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  omp_set_num_threads(threads);
  state.SetBytesProcessed(state.iterations() * n * 3 * static_cast<std::int64_t>(sizeof(double)));
}
BENCHMARK(BM_StreamTriad)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
BENCHMARK_MAIN();
