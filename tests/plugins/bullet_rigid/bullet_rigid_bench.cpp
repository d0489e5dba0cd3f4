// Step cost of the bullet_rigid solver: one advance() of a frame (1/24 s, 10 substeps of
// 1/240 s) for the configs/rigid_shells_falling.json scene once the shells are resting
// in contact, and for N free-falling spheres (the broadphase/world-rebuild overhead).
#include <benchmark/benchmark.h>

#include <fstream>

#include "shellflow/bullet_rigid/bullet_rigid_solver.hpp"

namespace {

using shellflow::bullet_rigid::BulletRigidSolver;

shellflow::sdk::Context context() {
  shellflow::sdk::Context c;
  c.instance_name = "shells";
  return c;
}

void BM_FallingShellsFrame(benchmark::State& state) {
  std::ifstream file(SHELLFLOW_SOURCE_DIR "/configs/rigid_shells_falling.json");
  const auto scene = nlohmann::json::parse(file);
  BulletRigidSolver solver(scene.at("solids").at(0), context());
  double t = 0.0;
  const double frame = 1.0 / 24.0;
  // Skip to t = 1.5 s, when the shells touch the ground and each other.
  for (int f = 0; f < 36; ++f, t += frame) solver.advance(t, frame, {});
  shellflow::sdk::StateBuffer at_rest;
  shellflow::sdk::StateWriter writer(at_rest);
  solver.save(writer);
  for (auto _ : state) {
    solver.advance(t, frame, {});
    state.PauseTiming();
    shellflow::sdk::StateReader reader(at_rest);  // measure the same frame every time
    solver.restore(reader);
    state.ResumeTiming();
  }
  shellflow::sdk::Metrics m;
  solver.advance(t, frame, {});
  solver.report(m);
  state.counters["contacts"] = m.values()[2].second;
}
BENCHMARK(BM_FallingShellsFrame)->Unit(benchmark::kMillisecond);

void BM_FreeSpheresFrame(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  nlohmann::json params = {{"bodies", nlohmann::json::array()}};
  for (int i = 0; i < n; ++i)
    params["bodies"].push_back(
        {{"name", std::to_string(i)},
         {"mesh", {{"type", "sphere"}, {"radius", 0.1}, {"subdivisions", 3}}},
         {"transform", {{"translate", {0.5 * i, 10.0, 0.0}}}}});
  BulletRigidSolver solver(params, context());
  double t = 0.0;
  for (auto _ : state) {
    solver.advance(t, 1.0 / 24.0, {});
    t += 1.0 / 24.0;
  }
  state.counters["triangles"] = 1280.0 * n;
}
BENCHMARK(BM_FreeSpheresFrame)->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
