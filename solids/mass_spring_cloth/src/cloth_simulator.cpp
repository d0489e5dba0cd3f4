#include "mass_spring_cloth/cloth_simulator.hpp"

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "mass_spring_cloth/aggregation_preconditioner.hpp"
#include "mass_spring_cloth/spring_element.hpp"
#include "mass_spring_cloth/strain_limiter.hpp"
#include "shellflow/linear/preconditioned_cg.hpp"
#include "shellflow/sdk/error.hpp"

namespace shellflow::cloth {

struct ClothSimulator::LinearSolvers {
  AggregationPreconditioner two_level;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholmod;
  bool cholmod_analysed = false;
};

namespace {

// Below this many items a loop runs serially: a parallel region costs more than it saves.
constexpr int kParallelThreshold = 4096;

Eigen::Vector3d node(const Eigen::VectorXd& x, int k) {
  return x.segment<3>(3 * k);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ClothSimulator::ClothSimulator(ClothModel model, const SolverSettings& solver,
                               const CollisionSettings& collision, const Eigen::Vector3d& gravity)
    : m_model(std::move(model)),
      m_solver(solver),
      m_collision(collision),
      m_gravity(gravity),
      m_linear(std::make_unique<LinearSolvers>()) {
  const int n = m_model.node_count();
  m_x = m_model.rest_positions;
  m_v = Eigen::VectorXd::Zero(3 * n);
  m_anchor = m_x;
  m_constraint.assign(n, kFree);
  build_pattern();
}

ClothSimulator::~ClothSimulator() = default;

void ClothSimulator::build_pattern() {
  const int n = m_model.node_count();
  const auto& springs = m_model.springs;
  std::vector<std::pair<int, int>> pairs;
  for (const auto& s : springs) pairs.emplace_back(s.i, s.j);
  for (const auto& b : m_model.bending)
    for (int k = 0; k < 4; ++k)
      for (int l = k + 1; l < 4; ++l) pairs.emplace_back(b.nodes[k], b.nodes[l]);
  m_system.build(n, pairs);

  m_spring_end_start.assign(n + 1, 0);
  for (const auto& s : springs) ++m_spring_end_start[s.i + 1], ++m_spring_end_start[s.j + 1];
  for (int k = 0; k < n; ++k) m_spring_end_start[k + 1] += m_spring_end_start[k];
  m_spring_ends.resize(m_spring_end_start[n]);
  std::vector<int> fill(m_spring_end_start.begin(), m_spring_end_start.end() - 1);
  for (int e = 0; e < static_cast<int>(springs.size()); ++e) {
    const auto& s = springs[e];
    m_spring_ends[fill[s.i]++] = {e, 1.0, m_system.find(s.i, s.j)};
    m_spring_ends[fill[s.j]++] = {e, -1.0, m_system.find(s.j, s.i)};
  }
  m_spring_force.resize(springs.size());
  m_spring_kv.resize(springs.size());
  m_spring_block.resize(springs.size());

  // Constant Hessian of the quadratic bending energy (Bergou et al. 2006), per unit k_b.
  m_bending_q.assign(m_system.block_count(), 0.0);
  for (const auto& b : m_model.bending)
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < 4; ++l)
        m_bending_q[m_system.find(b.nodes[k], b.nodes[l])] +=
            b.inverse_area * b.weights[k] * b.weights[l];
  m_last_dv = Eigen::VectorXd::Zero(3 * n);
  m_last_h = 0.0;
  m_linear->two_level.build(m_system);
}

void ClothSimulator::pin(int k) {
  if (k < 0 || k >= node_count()) throw Error("pin: node " + std::to_string(k) + " does not exist");
  m_constraint[k] = kPinned;
  m_anchor.segment<3>(3 * k) = m_x.segment<3>(3 * k);
  m_v.segment<3>(3 * k).setZero();
}

void ClothSimulator::attach(int k, const KinematicPath& path) {
  if (k < 0 || k >= node_count())
    throw Error("attach: node " + std::to_string(k) + " does not exist");
  m_paths.push_back(path);
  m_constraint[k] = static_cast<int>(m_paths.size()) - 1;
  m_anchor.segment<3>(3 * k) = m_x.segment<3>(3 * k);
}

void ClothSimulator::set_state(const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
  SHELLFLOW_ASSERT(x.size() == m_x.size() && v.size() == m_v.size());
  m_x = x;
  m_v = v;
}

void ClothSimulator::set_obstacles(sdk::ShellSet surfaces, double t) {
  std::vector<const void*> ids;
  for (const auto& s : surfaces) ids.push_back(s.triangles.get());
  if (ids != m_obstacle_ids) {
    m_obstacle_ids = ids;
    m_obstacle_triangles.clear();
    int offset = node_count();
    for (const auto& s : surfaces) {
      for (int t = 0; t < s.triangle_count(); ++t)
        m_obstacle_triangles.push_back({offset + (*s.triangles)(t, 0),
                                        offset + (*s.triangles)(t, 1),
                                        offset + (*s.triangles)(t, 2)});
      offset += s.node_count();
    }
    m_collision_topology_dirty = true;
  }
  m_obstacle_x.clear();
  m_obstacle_v.clear();
  for (const auto& s : surfaces)
    for (int k = 0; k < s.node_count(); ++k) {
      m_obstacle_x.push_back(s.positions.row(k).transpose());
      m_obstacle_v.push_back(s.velocities.rows() == s.positions.rows()
                                 ? Eigen::Vector3d(s.velocities.row(k).transpose())
                                 : Eigen::Vector3d::Zero());
    }
  m_obstacle_time = t;
}

void ClothSimulator::advance(double t, double dt) {
  const int substeps = std::max(m_solver.min_substeps,
                                static_cast<int>(std::ceil(dt / m_solver.max_substep - 1e-9)));
  const double h = dt / substeps;
  m_stats = StepStatistics{};
  m_stats.substeps = substeps;
  for (int s = 0; s < substeps; ++s) step(t + s * h, h);
}

Eigen::VectorXd ClothSimulator::forces(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const {
  const int n = node_count();
  Eigen::VectorXd f(3 * n);
  for (int k = 0; k < n; ++k)
    f.segment<3>(3 * k) =
        m_model.masses[k] * m_gravity - m_model.air_damping * m_model.node_areas[k] * node(v, k);
  if (m_external.size() == f.size()) f += m_external;
  for (const auto& s : m_model.springs) {
    const auto e = evaluate_spring(s, node(x, s.i), node(x, s.j), node(v, s.i), node(v, s.j), true);
    f.segment<3>(3 * s.i) += e.force_i;
    f.segment<3>(3 * s.j) -= e.force_i;
  }
  for (const auto& b : m_model.bending) {
    Eigen::Vector3d sx = Eigen::Vector3d::Zero(), sv = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) {
      sx += b.weights[k] * node(x, b.nodes[k]);
      sv += b.weights[k] * node(v, b.nodes[k]);
    }
    const Eigen::Vector3d g =
        b.inverse_area * (m_model.bending_stiffness * sx + m_model.bending_damping * sv);
    for (int k = 0; k < 4; ++k) f.segment<3>(3 * b.nodes[k]) -= b.weights[k] * g;
  }
  return f;
}

void ClothSimulator::force_jacobians(const Eigen::VectorXd& x, const Eigen::VectorXd& v, bool exact,
                                     Eigen::SparseMatrix<double>& dfdx,
                                     Eigen::SparseMatrix<double>& dfdv) const {
  const int n = node_count();
  std::vector<Eigen::Triplet<double>> tx, tv;
  const auto add = [](std::vector<Eigen::Triplet<double>>& t, int i, int j,
                      const Eigen::Matrix3d& B) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) t.emplace_back(3 * i + a, 3 * j + b, B(a, b));
  };
  for (int k = 0; k < n; ++k)
    add(tv, k, k, -m_model.air_damping * m_model.node_areas[k] * Eigen::Matrix3d::Identity());
  for (const auto& s : m_model.springs) {
    const auto e =
        evaluate_spring(s, node(x, s.i), node(x, s.j), node(v, s.i), node(v, s.j), exact);
    add(tx, s.i, s.i, e.dfdx), add(tx, s.j, s.j, e.dfdx), add(tx, s.i, s.j, -e.dfdx),
        add(tx, s.j, s.i, -e.dfdx);
    add(tv, s.i, s.i, e.dfdv), add(tv, s.j, s.j, e.dfdv), add(tv, s.i, s.j, -e.dfdv),
        add(tv, s.j, s.i, -e.dfdv);
  }
  for (const auto& b : m_model.bending)
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < 4; ++l) {
        const Eigen::Matrix3d I =
            b.inverse_area * b.weights[k] * b.weights[l] * Eigen::Matrix3d::Identity();
        add(tx, b.nodes[k], b.nodes[l], -m_model.bending_stiffness * I);
        add(tv, b.nodes[k], b.nodes[l], -m_model.bending_damping * I);
      }
  dfdx.resize(3 * n, 3 * n);
  dfdv.resize(3 * n, 3 * n);
  dfdx.setFromTriplets(tx.begin(), tx.end());
  dfdv.setFromTriplets(tv.begin(), tv.end());
}

void ClothSimulator::assemble(double h) {
  const int n = node_count();
  const auto& springs = m_model.springs;
  const bool exact = m_solver.exact_jacobian;
  const int spring_count = static_cast<int>(springs.size());
#pragma omp parallel for schedule(static) if (spring_count > kParallelThreshold)
  for (int e = 0; e < spring_count; ++e) {
    const auto& s = springs[e];
    const auto ev =
        evaluate_spring(s, node(m_x, s.i), node(m_x, s.j), node(m_v, s.i), node(m_v, s.j), exact);
    m_spring_force[e] = ev.force_i;
    m_spring_kv[e] = ev.dfdx * (node(m_v, s.i) - node(m_v, s.j));
    m_spring_block[e] = -(h * h) * ev.dfdx - h * ev.dfdv;
  }

  // Per node (one block row each, so no two threads write the same entry): mass, gravity,
  // drag and external force; its springs; and the bending force f = -k_b Q x - beta Q v
  // with constant df/dx = -k_b Q, df/dv = -beta Q (Bergou et al. 2006).
  m_force.resize(3 * n);
  m_kv.resize(3 * n);
  const bool external = m_external.size() == 3 * n;
  const double kb = m_model.bending_stiffness, beta = m_model.bending_damping;
  const double bending_diagonal = h * h * kb + h * beta;
#pragma omp parallel for schedule(static) if (n > kParallelThreshold)
  for (int i = 0; i < n; ++i) {
    for (int b = m_system.row_begin(i); b < m_system.row_end(i); ++b) m_system.block(b).setZero();
    const double drag = m_model.air_damping * m_model.node_areas[i];
    Eigen::Vector3d f = m_model.masses[i] * m_gravity - drag * node(m_v, i);
    if (external) f += m_external.segment<3>(3 * i);
    Eigen::Vector3d kv = Eigen::Vector3d::Zero();
    auto diagonal = m_system.block(m_system.diagonal(i));
    diagonal.diagonal().setConstant(m_model.masses[i] + h * drag);
    for (int p = m_spring_end_start[i]; p < m_spring_end_start[i + 1]; ++p) {
      const auto& end = m_spring_ends[p];
      f += end.sign * m_spring_force[end.spring];
      kv += end.sign * m_spring_kv[end.spring];
      diagonal += m_spring_block[end.spring];
      m_system.block(end.off_diagonal) -= m_spring_block[end.spring];
    }
    if (kb != 0.0 || beta != 0.0) {
      for (int b = m_system.row_begin(i); b < m_system.row_end(i); ++b) {
        const double q = m_bending_q[b];
        if (q == 0.0) continue;
        const int j = m_system.column(b);
        f -= q * (kb * node(m_x, j) + beta * node(m_v, j));
        kv -= q * kb * node(m_v, j);
        m_system.add_diagonal(b, bending_diagonal * q);
      }
    }
    m_force.segment<3>(3 * i) = f;
    m_kv.segment<3>(3 * i) = kv;
  }
}

void ClothSimulator::step(double t, double h) {
  const int n = node_count();
  auto clock = std::chrono::steady_clock::now();

  // Baraff–Witkin eq. (6): (M - h df/dv - h^2 df/dx) dv = h (f0 + h df/dx v0).
  assemble(h);
  Eigen::VectorXd rhs = h * (m_force + h * m_kv);

  // Constrained nodes: dv is known; eliminate it (rows and columns, keeping symmetry).
  Eigen::VectorXd known = Eigen::VectorXd::Zero(3 * n);
  std::vector<char> fixed(n, 0);
  bool any_fixed = false;
  for (int k = 0; k < n; ++k) {
    if (m_constraint[k] == kFree) continue;
    fixed[k] = 1;
    any_fixed = true;
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    if (m_constraint[k] >= 0)
      target = (m_anchor.segment<3>(3 * k) + m_paths[m_constraint[k]].translation(t + h) -
                node(m_x, k)) /
               h;
    known.segment<3>(3 * k) = target - node(m_v, k);
  }
  if (any_fixed) {
#pragma omp parallel for schedule(static) if (n > kParallelThreshold)
    for (int i = 0; i < n; ++i) {
      if (fixed[i]) {
        for (int b = m_system.row_begin(i); b < m_system.row_end(i); ++b)
          m_system.block(b).setZero();
        m_system.add_diagonal(m_system.diagonal(i), 1.0);
        rhs.segment<3>(3 * i) = known.segment<3>(3 * i);
        continue;
      }
      for (int b = m_system.row_begin(i); b < m_system.row_end(i); ++b) {
        const int j = m_system.column(b);
        if (!fixed[j]) continue;
        rhs.segment<3>(3 * i) -= m_system.block(b) * known.segment<3>(3 * j);
        m_system.block(b).setZero();
      }
    }
  }
  m_stats.assembly_seconds += seconds_since(clock);
  clock = std::chrono::steady_clock::now();

  Eigen::VectorXd dv;
  if (m_solver.linear_solver == LinearSolverKind::ConjugateGradient) {
    // Warm start: the last velocity change scaled to this step (dv ~ acceleration * h).
    dv = m_last_h > 0.0 ? Eigen::VectorXd(m_last_dv * (h / m_last_h)) : Eigen::VectorXd(known);
    for (int k = 0; k < n; ++k)
      if (fixed[k]) dv.segment<3>(3 * k) = known.segment<3>(3 * k);
    m_system.compress_symmetric();
    m_linear->two_level.compute(m_system, fixed);
    const auto solve = linear::preconditioned_cg(m_system, m_linear->two_level, rhs, dv,
                                                 m_solver.cg_tolerance,
                                                 m_solver.cg_max_iterations);
    m_stats.cg_iterations += solve.iterations;
    m_stats.coarse_unknowns = 3 * m_linear->two_level.aggregate_count();
    m_stats.cg_error = std::max(m_stats.cg_error, solve.relative_residual);
  } else {
    auto& lin = *m_linear;
    const auto& A = m_system.to_scalar();
    if (!lin.cholmod_analysed) {
      lin.cholmod.analyzePattern(A);
      lin.cholmod_analysed = true;
    }
    lin.cholmod.factorize(A);
    if (lin.cholmod.info() != Eigen::Success)
      throw NumericalError(
          "mass_spring_cloth: CHOLMOD could not factor the implicit system "
          "(not positive definite); use the default CG solver or smaller steps");
    dv = lin.cholmod.solve(rhs);
  }
  if (!dv.allFinite())
    throw NumericalError(
        "mass_spring_cloth: the implicit solve produced non-finite velocities; "
        "lower the stiffness or the step (solver/max_substep)");
  m_last_dv = dv;
  m_last_h = h;
  m_stats.solve_seconds += seconds_since(clock);
  clock = std::chrono::steady_clock::now();
  Eigen::VectorXd v1 = m_v + dv;

  // Collisions: analytic colliders, then other solids' surfaces and self-collision.
  std::vector<Eigen::Vector3d> pop(n, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3d> contact_normal(n, Eigen::Vector3d::Zero());
  if (!m_colliders.empty()) contact_normal = resolve_collider_contacts(m_x, v1, h, pop);
  // Strain limiting before the self-collision pass, which has the last word on velocities;
  // constrained nodes do not move in it, nodes on a collider only slide along it.
  if (m_solver.max_strain > 0.0) {
    std::vector<double> inverse_mass(n, 0.0);
    for (int k = 0; k < n; ++k)
      if (!fixed[k]) inverse_mass[k] = 1.0 / m_model.masses[k];
    m_stats.strain_corrections += limit_strain(m_model, m_x, v1, inverse_mass, contact_normal, h,
                                               m_solver.max_strain, m_solver.strain_limit_sweeps)
                                      .corrections;
  }
  const bool obstacles = !m_obstacle_triangles.empty();
  if (m_collision.self_collision || obstacles) {
    if (m_collision_topology_dirty) {
      std::vector<std::array<int, 3>> triangles;
      for (int k = 0; k < m_model.triangles.rows(); ++k)
        triangles.push_back(
            {m_model.triangles(k, 0), m_model.triangles(k, 1), m_model.triangles(k, 2)});
      triangles.insert(triangles.end(), m_obstacle_triangles.begin(), m_obstacle_triangles.end());
      std::vector<Eigen::Vector3d> rest(n);
      for (int k = 0; k < n; ++k) rest[k] = node(m_model.rest_positions, k);
      // Shapes the self-collision hierarchy, rebuilt only if the cloth's triangles change.
      m_collision_solver.set_topology(triangles, n, m_collision.self_collision, rest);
      m_collision_solver.set_parameters(m_collision.thickness, m_collision.friction,
                                        m_collision.ccd_iterations);
      m_collision_topology_dirty = false;
    }
    const size_t total = n + m_obstacle_x.size();
    std::vector<Eigen::Vector3d> x0(total), v(total);
    std::vector<double> inverse_mass(total, 0.0);
    for (int k = 0; k < n; ++k) {
      x0[k] = node(m_x, k);
      v[k] = node(v1, k);
      inverse_mass[k] = fixed[k] ? 0.0 : 1.0 / m_model.masses[k];
    }
    for (size_t k = 0; k < m_obstacle_x.size(); ++k) {
      x0[n + k] = m_obstacle_x[k] + (t - m_obstacle_time) * m_obstacle_v[k];
      v[n + k] = m_obstacle_v[k];
    }
    const auto c = m_collision_solver.resolve(x0, v, inverse_mass, h);
    m_stats.collisions.proximity_contacts += c.proximity_contacts;
    m_stats.collisions.ccd_collisions += c.ccd_collisions;
    m_stats.collisions.impact_zones += c.impact_zones;
    m_stats.collisions.candidate_pairs = c.candidate_pairs;
    m_stats.collisions.culled_patches = c.culled_patches;
    m_stats.collisions.broad_phases += c.broad_phases;
    for (int k = 0; k < n; ++k) v1.segment<3>(3 * k) = v[k];
  }

  m_stats.collision_seconds += seconds_since(clock);

  m_x += h * v1;
  for (int k = 0; k < n; ++k) v1.segment<3>(3 * k) -= pop[k];
  m_v = v1;
  if (!m_x.allFinite()) throw NumericalError("mass_spring_cloth: non-finite node positions");
}

std::vector<Eigen::Vector3d> ClothSimulator::resolve_collider_contacts(
    const Eigen::VectorXd& x0, Eigen::VectorXd& v, double h, std::vector<Eigen::Vector3d>& pop) {
  const int n = node_count();
  const double thickness = m_collision.thickness, mu = m_collision.friction;
  int contacts = 0;
  std::vector<Eigen::Vector3d> touching(n, Eigen::Vector3d::Zero());
#pragma omp parallel for schedule(static) reduction(+ : contacts) if (n > kParallelThreshold)
  for (int k = 0; k < n; ++k) {
    if (m_constraint[k] != kFree) continue;
    Eigen::Vector3d vk = v.segment<3>(3 * k);
    bool touched = false;
    for (const auto& collider : m_colliders) {
      Eigen::Vector3d normal;
      const double phi = collider.signed_distance(node(x0, k) + h * vk, normal);
      if (phi >= thickness) continue;
      touched = true;
      touching[k] = normal;
      // Inelastic contact with Coulomb friction on the node velocity (Bridson 2002 §7.3).
      const double vn = vk.dot(normal);
      if (vn < 0.0) {
        const Eigen::Vector3d vt = vk - vn * normal;
        const double vt_norm = vt.norm();
        const double keep = vt_norm > 0.0 ? std::max(0.0, 1.0 - mu * (-vn) / vt_norm) : 0.0;
        vk = keep * vt;
      }
      // Position correction to the thickness, as a velocity removed again after the step.
      Eigen::Vector3d n2;
      const double phi2 = collider.signed_distance(node(x0, k) + h * vk, n2);
      if (phi2 < thickness) {
        const Eigen::Vector3d push = (thickness - phi2) / h * n2;
        vk += push;
        pop[k] += push;
      }
    }
    if (touched) ++contacts;
    v.segment<3>(3 * k) = vk;
  }
  m_stats.collider_contacts += contacts;
  return touching;
}

double ClothSimulator::kinetic_energy() const {
  double e = 0.0;
  for (int k = 0; k < node_count(); ++k) e += 0.5 * m_model.masses[k] * node(m_v, k).squaredNorm();
  return e;
}

double ClothSimulator::potential_energy() const {
  double e = 0.0;
  for (int k = 0; k < node_count(); ++k) e -= m_model.masses[k] * m_gravity.dot(node(m_x, k));
  for (const auto& s : m_model.springs) e += spring_energy(s, node(m_x, s.i), node(m_x, s.j));
  for (const auto& b : m_model.bending) {
    Eigen::Vector3d sx = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) sx += b.weights[k] * node(m_x, b.nodes[k]);
    e += 0.5 * m_model.bending_stiffness * b.inverse_area * sx.squaredNorm();
  }
  return e;
}

double ClothSimulator::max_structural_strain() const {
  double strain = 0.0;
  for (int e = 0; e < m_model.structural_count; ++e) {
    const auto& s = m_model.springs[e];
    strain = std::max(strain, (node(m_x, s.i) - node(m_x, s.j)).norm() / s.rest_length - 1.0);
  }
  return strain;
}

void ClothSimulator::save(sdk::StateWriter& out) const {
  out.write<std::int64_t>(node_count());
  out.write_matrix(m_x);
  out.write_matrix(m_v);
  out.write_matrix(m_last_dv);
  out.write<double>(m_last_h);
}

void ClothSimulator::restore(sdk::StateReader& in) {
  const auto n = in.read<std::int64_t>();
  if (n != node_count())
    throw Error("mass_spring_cloth restore(): the state holds " + std::to_string(n) +
                " nodes, this cloth has " + std::to_string(node_count()));
  in.read_matrix(m_x);
  in.read_matrix(m_v);
  in.read_matrix(m_last_dv);
  m_last_h = in.read<double>();
}

}  // namespace shellflow::cloth
