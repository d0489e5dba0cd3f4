#pragma once
// Strain limiting on the structural springs, after Provot ("Deformation constraints in a
// mass-spring model to describe rigid cloth behavior", Graphics Interface 1995) and
// Bridson, Marino, Fedkiw 2003 ("Simulation of clothing with folds and wrinkles", §6),
// applied to the end-of-step velocities: a spring whose length at the end of the step,
// x + h v, exceeds (1 + max_strain) times its rest length gets equal and opposite
// velocity changes, weighted by inverse mass, that bring it back to the limit.
// Gauss–Seidel sweeps over the springs, a few times.
//
// Why it is needed: contact is resolved after the implicit solve, so a node stopped by
// a collider cannot tell its springs within the same step; the neighbours that are not
// yet touching keep falling and the springs between them over-stretch in one step (tens
// of percent at frame steps). Coulomb friction then holds the stretched nodes on the
// collider, and the strain stays. The limiter couples the stopped nodes to their
// neighbours in the step itself: the free ones are pulled along, and nodes in contact
// may slide along the collider (the pass never moves them into it; it is an internal
// constraint of the cloth, stronger than the contact's friction).

#include <Eigen/Core>
#include <vector>

#include "mass_spring_cloth/cloth_model.hpp"

namespace shellflow::cloth {

struct StrainLimitStatistics {
  int corrections = 0;  ///< spring corrections over all sweeps
  int sweeps = 0;
};

/// Changes `v` (3n) so that no structural spring is longer than (1 + max_strain) L0 at
/// x + h v, up to `max_sweeps` Gauss–Seidel sweeps. Nodes with zero `inverse_mass` keep
/// their velocity; a node with a nonzero `contact_normal` gets no velocity change along
/// -normal (into the collider). Without contacts the total momentum is unchanged.
StrainLimitStatistics limit_strain(const ClothModel& model, const Eigen::VectorXd& x,
                                   Eigen::VectorXd& v, const std::vector<double>& inverse_mass,
                                   const std::vector<Eigen::Vector3d>& contact_normal, double h,
                                   double max_strain, int max_sweeps);

}  // namespace shellflow::cloth
