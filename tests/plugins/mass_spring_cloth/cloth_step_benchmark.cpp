// Step time of the mass-spring cloth at the paper's cloth size: 101 x 151 nodes, 30,000
// triangles (Guendelman et al. 2005 water example 6: a 0.5 x 0.75 m curtain pinned at its
// two top corners), self-collision on, at dt = 1/240 s and 1/24 s, CG or CHOLMOD; and the
// same sheet folded onto itself on the floor (dense self-contact), with CG.
//   build-<you>/bin/bench_mass_spring_cloth --benchmark_min_time=5x

#include <benchmark/benchmark.h>

#include "mass_spring_cloth/cloth_simulator.hpp"
#include "shellflow/geometry/mesh_generators.hpp"

namespace {

using namespace shellflow;

void BM_ClothStep(benchmark::State& state) {
  const double dt = 1.0 / static_cast<double>(state.range(0));
  const bool cholmod = state.range(1) != 0;
  auto mesh = geometry::make_grid(0.5, 0.75, 101, 151, geometry::GridPattern::Herringbone);
  cloth::ClothMaterial material;
  material.surface_density = 1.0;
  cloth::SolverSettings solver;
  solver.max_substep = dt;
  solver.linear_solver =
      cholmod ? cloth::LinearSolverKind::Cholmod : cloth::LinearSolverKind::ConjugateGradient;
  cloth::CollisionSettings collision;
  collision.thickness = 0.00125;  // a quarter of the 5 mm spacing
  collision.self_collision = true;
  cloth::ClothSimulator sim(cloth::build_cloth_model(mesh.positions, mesh.triangles, material),
                            solver, collision, Eigen::Vector3d(0, -9.81, 0));
  sim.pin(101 * 150);
  sim.pin(101 * 151 - 1);
  // Warm up: let the curtain start to fall and fold so contacts and CG work are typical.
  double t = 0.0;
  for (int s = 0; s < 5; ++s, t += dt) sim.advance(t, dt);
  long cg = 0, contacts = 0, steps = 0;
  double assembly = 0.0, solve = 0.0, collision_time = 0.0;
  for (auto _ : state) {
    sim.advance(t, dt);
    t += dt;
    cg += sim.statistics().cg_iterations;
    assembly += sim.statistics().assembly_seconds;
    solve += sim.statistics().solve_seconds;
    collision_time += sim.statistics().collision_seconds;
    contacts +=
        sim.statistics().collisions.proximity_contacts + sim.statistics().collisions.ccd_collisions;
    ++steps;
  }
  state.counters["cg_iterations"] = static_cast<double>(cg) / steps;
  state.counters["contacts"] = static_cast<double>(contacts) / steps;
  // Where the time goes, per step [ms].
  state.counters["assembly_ms"] = 1e3 * assembly / steps;
  state.counters["solve_ms"] = 1e3 * solve / steps;
  state.counters["collision_ms"] = 1e3 * collision_time / steps;
  state.counters["candidate_pairs"] = sim.statistics().collisions.candidate_pairs;
  state.counters["culled_patches"] = sim.statistics().collisions.culled_patches;
  state.counters["broad_phases"] = sim.statistics().collisions.broad_phases;
  state.counters["coarse_unknowns"] = sim.statistics().coarse_unknowns;
  state.counters["triangles"] = static_cast<double>(mesh.triangles.rows());
}

BENCHMARK(BM_ClothStep)
    ->ArgNames({"inv_dt", "cholmod"})
    ->Args({240, 0})
    ->Args({24, 0})
    ->Args({240, 1})
    ->Args({24, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

// Self-contact everywhere: the same 30,000-triangle sheet lying on the floor (a plane
// collider), folded in half along its long side with the upper half 2 thicknesses above
// the lower one, falling onto it. Every upper node has a lower triangle within reach.
void BM_ClothFoldedStep(benchmark::State& state) {
  const double dt = 1.0 / static_cast<double>(state.range(0));
  const int nu = 101, nv = 151, fold = 75;
  const double spacing = 0.005, thickness = 0.00125;
  auto mesh = geometry::make_grid(spacing * (nu - 1), spacing * (nv - 1), nu, nv,
                                  geometry::GridPattern::Herringbone);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int k = i + nu * j;
      const double x = mesh.positions(k, 0), s = (j - fold) * spacing;
      mesh.positions.row(k) = j <= fold ? Eigen::RowVector3d(x, thickness, s)
                                        : Eigen::RowVector3d(x, 3.0 * thickness, -s);
    }
  cloth::ClothMaterial material;
  material.surface_density = 1.0;
  material.bending_stiffness = 0.0;  // the fold is the rest shape
  cloth::SolverSettings solver;
  solver.max_substep = dt;
  cloth::CollisionSettings collision;
  collision.thickness = thickness;
  cloth::ClothSimulator sim(cloth::build_cloth_model(mesh.positions, mesh.triangles, material),
                            solver, collision, Eigen::Vector3d(0, -9.81, 0));
  sim.add_collider(
      cloth::AnalyticCollider::plane(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()));
  double t = 0.0;
  for (int s = 0; s < 5; ++s, t += dt) sim.advance(t, dt);
  long cg = 0, contacts = 0, ccd = 0, broad_phases = 0, steps = 0;
  double assembly = 0.0, solve = 0.0, collision_time = 0.0;
  for (auto _ : state) {
    sim.advance(t, dt);
    t += dt;
    cg += sim.statistics().cg_iterations;
    assembly += sim.statistics().assembly_seconds;
    solve += sim.statistics().solve_seconds;
    collision_time += sim.statistics().collision_seconds;
    contacts +=
        sim.statistics().collisions.proximity_contacts + sim.statistics().collisions.ccd_collisions;
    ccd += sim.statistics().collisions.ccd_collisions;
    broad_phases += sim.statistics().collisions.broad_phases;
    ++steps;
  }
  state.counters["cg_iterations"] = static_cast<double>(cg) / steps;
  state.counters["contacts"] = static_cast<double>(contacts) / steps;
  state.counters["assembly_ms"] = 1e3 * assembly / steps;
  state.counters["solve_ms"] = 1e3 * solve / steps;
  state.counters["collision_ms"] = 1e3 * collision_time / steps;
  state.counters["ccd_collisions"] = static_cast<double>(ccd) / steps;
  state.counters["broad_phases"] = static_cast<double>(broad_phases) / steps;
  state.counters["candidate_pairs"] = sim.statistics().collisions.candidate_pairs;
  state.counters["culled_patches"] = sim.statistics().collisions.culled_patches;
  state.counters["max_strain"] = sim.max_structural_strain();
}

BENCHMARK(BM_ClothFoldedStep)
    ->ArgNames({"inv_dt"})
    ->Args({240})
    ->Args({24})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

}  // namespace

BENCHMARK_MAIN();
