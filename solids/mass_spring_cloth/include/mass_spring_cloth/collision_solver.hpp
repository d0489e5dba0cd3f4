#pragma once
// Cloth self-collision and cloth–mesh collision by velocity impulses, after Bridson,
// Fedkiw, Anderson 2002 ("Robust Treatment of Collisions, Contact and Friction for Cloth
// Animation"):
//  1. proximity (§7.2): point–triangle and edge–edge pairs closer than the thickness at
//     the start of the step get an inelastic impulse plus a repulsion that separates them
//     by a tenth of the overlap per step, with Coulomb friction (§7.3);
//  2. continuous collision (§7.4): moving point–triangle and edge–edge pairs are tested
//     for coplanarity during the step (a cubic, solved by the framework's
//     geometry::cubic_near_roots after a Bernstein sign test that rejects most pairs);
//     colliding pairs get inelastic impulses, repeated for a few passes;
//  3. rigid impact zones (§7.4, simplified to translations): nodes of pairs still colliding
//     are merged into zones that move with their mass-weighted mean velocity, until no
//     pair collides. A rigid translation cannot make a zone's own elements collide.
// Nodes of other solids' surfaces enter as extra nodes with zero inverse mass, so the
// same passes keep the cloth on its side of those surfaces. Candidate pairs come from
// ContactBroadPhase (a fixed patch hierarchy, refit per step, whose flat patches skip
// self-collision by normal cones) for the step's motion with a margin, and are reused by
// the later passes while no node strays beyond that margin.
// Contacts are applied in the order of their pair, so the result does not depend on the
// thread count or on the hierarchy's history (save/restore stays bit-for-bit).

#include <Eigen/Core>
#include <array>
#include <vector>

#include "mass_spring_cloth/contact_broad_phase.hpp"

namespace shellflow::cloth {

struct CollisionStatistics {
  int proximity_contacts = 0;
  int ccd_collisions = 0;   ///< pairs found by the continuous passes (all passes)
  int impact_zones = 0;     ///< zones left after the impact-zone loop
  int candidate_pairs = 0;  ///< point–triangle + edge–edge pairs from the last broad phase
  int broad_phases = 0;     ///< broad-phase searches (the candidates are reused in between)
  int culled_patches = 0;   ///< cloth patches skipped as self-collision-free, last broad phase
};

class CollisionSolver {
 public:
  using Vectors = std::vector<Eigen::Vector3d>;

  /// Topology: triangles over nodes [0, n); edges are derived from the triangles. Without
  /// self-collision only pairs touching a node >= `cloth_nodes` (an obstacle) count.
  /// `rest_positions` (the cloth's nodes) shape the self-collision hierarchy.
  void set_topology(const std::vector<std::array<int, 3>>& triangles, int cloth_nodes,
                    bool self_collision, const Vectors& rest_positions);
  void set_parameters(double thickness, double friction, int ccd_passes);

  /// Changes `v` so that moving from `x0` by h * v neither leaves pairs closer than the
  /// thickness approaching nor lets any point pass through any triangle or edge through
  /// edge. Nodes with zero inverse mass keep their velocity.
  CollisionStatistics resolve(const Vectors& x0, Vectors& v,
                              const std::vector<double>& inverse_mass, double h);

 private:
  struct Contact {
    std::array<int, 4> nodes;       ///< point/triangle or edge/edge nodes
    std::array<double, 4> weights;  ///< relative velocity = sum w_k v_k
    Eigen::Vector3d normal;
    double target_speed;  ///< wanted relative normal velocity [m/s]
  };
  /// A contact with its pair: (0, node, triangle) or (1, edge, edge); the sort key.
  using Keyed = std::pair<std::array<int, 3>, Contact>;

  /// Candidates for moving from x0 by h * v, refreshed only when some node has moved
  /// farther than the margin from the motion they were found for.
  void update_candidates(const Vectors& x0, const Vectors& v, double h, CollisionStatistics& stats);
  /// Also records each candidate's distance at the start (or a lower bound of it).
  void proximity_contacts(const Vectors& x0, const Vectors& v,
                          const std::vector<double>& inverse_mass, double h,
                          std::vector<Contact>& out);
  void ccd_contacts(const Vectors& x0, const Vectors& v, const std::vector<double>& inverse_mass,
                    double h, const std::vector<char>* active, std::vector<Contact>& out) const;
  void apply(const Contact& c, Vectors& v, const std::vector<double>& inverse_mass,
             double friction) const;

  std::vector<std::array<int, 3>> m_triangles;
  double m_thickness = 1e-3;
  double m_friction = 0.0;
  int m_ccd_passes = 6;
  ContactBroadPhase m_broad_phase;
  ContactCandidates m_candidates;
  Vectors m_candidate_motion;  ///< h * v the candidates were found for
  /// Per candidate, a lower bound of its distance at the start of the step (0: unknown).
  /// A pair farther apart than its nodes can move towards each other cannot collide, so
  /// the continuous passes skip it without solving its cubic.
  std::vector<double> m_pt_distance, m_ee_distance;
  bool m_candidates_valid = false;
};

}  // namespace shellflow::cloth
