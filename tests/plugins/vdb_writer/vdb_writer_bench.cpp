// VDB frame cost: density, temperature (cell) and velocity (node) of an n^3 grid with a
// plume filling about a sixth of it, written to a file (Blosc/zip compression as default).

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "shellflow/vdb_writer/vdb_frame.hpp"
#include "synthetic_fluid.hpp"

namespace {

using namespace shellflow;

void BM_VdbFrame(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const double dx = 1.0 / n;
  writer_testing::SyntheticFluid fluid;
  auto plume = [](const Eigen::Vector3d& x) {
    const double r2 = (x.x() - 0.5) * (x.x() - 0.5) + (x.z() - 0.5) * (x.z() - 0.5);
    return r2 < 0.05 ? (0.05 - r2) * 20.0 * x.y() : 0.0;
  };
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * dx);
  fluid.add("density", sdk::FieldView::Location::Cell, half, dx, {n, n, n}, 1).fill(0, plume);
  fluid.add("temperature", sdk::FieldView::Location::Cell, half, dx, {n, n, n}, 1)
      .fill(0, [&](const Eigen::Vector3d& x) { return 30.0 * plume(x); });
  auto& v = fluid.add("velocity", sdk::FieldView::Location::Node, Eigen::Vector3d::Zero(), dx,
                      {n + 1, n + 1, n + 1}, 3);
  v.fill(1, [&](const Eigen::Vector3d& x) { return 2.0 * plume(x); });
  const auto fields = fluid.fields();
  const auto folder = std::filesystem::temp_directory_path() /
                      ("shellflow_vdb_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  vdb_writer::VdbOptions options;
  options.background_tolerance = 1e-4;
  for (auto _ : state)
    vdb_writer::write_vdb_frame(folder / "frame.vdb", fields, options, {"bench", 0, 0.0});
  state.counters["file_MB"] =
      static_cast<double>(std::filesystem::file_size(folder / "frame.vdb")) / 1e6;
  std::filesystem::remove_all(folder);
}
BENCHMARK(BM_VdbFrame)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
