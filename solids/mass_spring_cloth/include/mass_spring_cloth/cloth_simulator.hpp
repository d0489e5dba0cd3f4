#pragma once
// The cloth solver proper: implicit backward Euler on a mass-spring cloth (Baraff and
// Witkin, "Large Steps in Cloth Simulation", SIGGRAPH 1998, §3 eq. (6)):
//   (M - h df/dv - h^2 df/dx) dv = h (f0 + h df/dx v0),  x1 = x0 + h (v0 + dv),
// one linearised step per substep, solved by CG with a two-level preconditioner (block
// Jacobi + an aggregation coarse space, aggregation_preconditioner.hpp; default) or a
// CHOLMOD supernodal Cholesky. The system lives in a fixed block pattern refilled in place
// each step (block_sparse_matrix.hpp); CG starts from the last step's velocity change,
// scaled to the new step, which for smooth motion is most of the answer. Pinned and
// path-driven nodes are eliminated from the system (their dv is known). After the solve,
// analytic colliders, the strain limiter (strain_limiter.hpp), other solids' surfaces and
// the cloth itself act on the velocities (collision_solver.hpp).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "mass_spring_cloth/analytic_collider.hpp"
#include "mass_spring_cloth/block_sparse_matrix.hpp"
#include "mass_spring_cloth/cloth_model.hpp"
#include "mass_spring_cloth/cloth_settings.hpp"
#include "mass_spring_cloth/collision_solver.hpp"
#include "mass_spring_cloth/kinematic_path.hpp"
#include "shellflow/sdk/shell_surface.hpp"
#include "shellflow/sdk/state_buffer.hpp"

namespace shellflow::cloth {

struct StepStatistics {
  int substeps = 0;
  int cg_iterations = 0;           ///< summed over the substeps of the last advance()
  double cg_error = 0.0;           ///< largest relative residual of those solves
  int coarse_unknowns = 0;         ///< size of the CG preconditioner's coarse system
  int collider_contacts = 0;       ///< node–analytic-collider contacts (summed over substeps)
  int strain_corrections = 0;      ///< spring corrections of the strain limiter
  CollisionStatistics collisions;  ///< summed over substeps
  // Wall-clock time of the parts of the substeps [s], for benchmarks and profiling.
  double assembly_seconds = 0.0;   ///< forces, Jacobians, system matrix, constraints
  double solve_seconds = 0.0;      ///< the linear solve (preconditioner included)
  double collision_seconds = 0.0;  ///< colliders, other solids and self-collision
};

class ClothSimulator {
 public:
  ClothSimulator(ClothModel model, const SolverSettings& solver, const CollisionSettings& collision,
                 const Eigen::Vector3d& gravity);
  ~ClothSimulator();
  ClothSimulator(const ClothSimulator&) = delete;
  ClothSimulator& operator=(const ClothSimulator&) = delete;

  /// Holds a node at its current position with zero velocity.
  void pin(int node);
  /// Moves a node along `path`: position = its current position + path.translation(t).
  void attach(int node, const KinematicPath& path);
  void add_collider(const AnalyticCollider& collider) { m_colliders.push_back(collider); }
  /// Other solids' surfaces at the start of the next advance(); extrapolated linearly
  /// with their node velocities over the substeps.
  void set_obstacles(sdk::ShellSet surfaces, double t);
  /// Per-node external force [N] (3n entries), held over the next advance(); empty: none.
  void set_external_forces(Eigen::VectorXd forces) { m_external = std::move(forces); }

  /// Advance from t to t + dt in max(min_substeps, ceil(dt / max_substep)) substeps.
  void advance(double t, double dt);
  /// One backward Euler substep from t to t + h.
  void step(double t, double h);

  const ClothModel& model() const { return m_model; }
  int node_count() const { return m_model.node_count(); }
  const Eigen::VectorXd& positions() const { return m_x; }
  const Eigen::VectorXd& velocities() const { return m_v; }
  void set_state(const Eigen::VectorXd& x, const Eigen::VectorXd& v);
  bool is_constrained(int node) const { return m_constraint[node] != kFree; }

  /// Total force at (x, v) [N], gravity and external forces included.
  Eigen::VectorXd forces(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const;
  /// df/dx and df/dv at (x, v) as used by the solve (`exact` per SolverSettings).
  void force_jacobians(const Eigen::VectorXd& x, const Eigen::VectorXd& v, bool exact,
                       Eigen::SparseMatrix<double>& dfdx, Eigen::SparseMatrix<double>& dfdv) const;

  double kinetic_energy() const;
  /// Gravity + springs + bending [J], gravity measured from the origin.
  double potential_energy() const;
  double max_structural_strain() const;

  const StepStatistics& statistics() const { return m_stats; }

  void save(sdk::StateWriter& out) const;
  void restore(sdk::StateReader& in);

 private:
  static constexpr int kFree = -2;
  static constexpr int kPinned = -1;

  void build_pattern();
  /// Forces, df/dx v and the system M - h df/dv - h^2 df/dx into m_system, m_force, m_kv.
  void assemble(double h);
  /// Returns per node the outward normal of the collider it touched (zero: none).
  std::vector<Eigen::Vector3d> resolve_collider_contacts(const Eigen::VectorXd& x0,
                                                         Eigen::VectorXd& v, double h,
                                                         std::vector<Eigen::Vector3d>& pop);

  ClothModel m_model;
  SolverSettings m_solver;
  CollisionSettings m_collision;
  Eigen::Vector3d m_gravity;

  Eigen::VectorXd m_x, m_v, m_external;
  std::vector<int> m_constraint;  ///< per node: kFree, kPinned or a path index
  std::vector<KinematicPath> m_paths;
  Eigen::VectorXd m_anchor;  ///< positions of constrained nodes when constrained
  std::vector<AnalyticCollider> m_colliders;

  // Other solids' surfaces (appended after the cloth nodes in the collision mesh).
  std::vector<Eigen::Vector3d> m_obstacle_x, m_obstacle_v;
  std::vector<std::array<int, 3>> m_obstacle_triangles;
  std::vector<const void*> m_obstacle_ids;
  double m_obstacle_time = 0.0;
  CollisionSolver m_collision_solver;
  bool m_collision_topology_dirty = true;

  BlockSparseMatrix m_system;
  /// Per node, the springs at it: spring index, +1 if the node is the spring's i, -1 if
  /// its j, and the block (node, other end) in the node's block row. CSR by node.
  struct SpringEnd {
    int spring = 0;
    double sign = 1.0;
    int off_diagonal = 0;
  };
  std::vector<int> m_spring_end_start;
  std::vector<SpringEnd> m_spring_ends;
  std::vector<double> m_bending_q;  ///< per block, Q_ij of the bending energy (times I)
  // Per-step work arrays (kept to avoid allocation): per spring its force on node i,
  // df_i/dx_i (v_i - v_j) and -h^2 df_i/dx_i - h df_i/dv_i.
  std::vector<Eigen::Vector3d> m_spring_force, m_spring_kv;
  std::vector<Eigen::Matrix3d> m_spring_block;
  Eigen::VectorXd m_force, m_kv;
  Eigen::VectorXd m_last_dv;  ///< velocity change of the last substep (CG's warm start)
  double m_last_h = 0.0;      ///< its step; 0 before the first substep

  struct LinearSolvers;
  std::unique_ptr<LinearSolvers> m_linear;
  StepStatistics m_stats;
};

}  // namespace shellflow::cloth
