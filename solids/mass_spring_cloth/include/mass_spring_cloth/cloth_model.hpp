#pragma once
// The discrete cloth: lumped node masses, springs and bending stencils built from a
// triangle mesh and a material in physical units.
//
// Springs (a mass-spring model in the manner of Baraff–Witkin 1998 / Bridson et al. 2003):
//  - structural: every mesh edge; spring constant k = (4/5) Y A_e / L0^2, with A_e the area
//    of the edge's triangles. The 4/5 makes a regular or herringbone grid store exactly
//    Y eps^2 / 2 per unit area under a strain eps along a grid axis (the axis edge and the
//    quad diagonal both stretch; the diagonal by eps/2 of its length), so results do not
//    depend on the grid spacing.
//  - shear: for each interior edge, a spring between the two opposite nodes (in a grid,
//    across a diagonal edge this is the quad's other diagonal); k = G A_e / L0^2.
// Bending: the quadratic bending energy of Bergou, Wardetzky, Harmon, Zorin, Grinspun,
//  "A Quadratic Bending Model for Inextensible Surfaces" (SGP 2006): per interior edge
//  E = (k_b / 2) |sum_k w_k x_k|^2 / (A_1 + A_2), cotangent weights w from the rest shape.
//  For a near-inextensible cloth |sum w x| = |e| * 2 sin(theta/2), so this is the discrete
//  shells energy k_b/2 * |e|^2 theta^2 / A_e. Chosen over bending springs across edge
//  pairs (which have zero stiffness at the flat state, their length changes with theta^2)
//  and over the dihedral-angle element of Bridson et al. 2003 (whose Hessian is costly and
//  non-constant): the force is linear in positions, so its Jacobian is exact and constant,
//  assembled once. Limitation: the rest shape of the bending term is flat.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "mass_spring_cloth/cloth_settings.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::cloth {

struct Spring {
  int i = 0;
  int j = 0;
  double rest_length = 0.0;
  double stiffness = 0.0;  ///< spring constant [N/m]
  double damping = 0.0;    ///< along the spring [N s/m]
};

/// One interior edge (a, b) with opposite nodes c (first triangle) and d (second).
struct BendingStencil {
  std::array<int, 4> nodes{};       ///< a, b, c, d
  std::array<double, 4> weights{};  ///< cotangent weights (Bergou et al. 2006)
  double inverse_area = 0.0;        ///< 1 / (A_1 + A_2) at rest [1/m^2]
};

struct ClothModel {
  Eigen::VectorXd rest_positions;  ///< 3n, node k at segment(3k, 3)
  Eigen::VectorXd masses;          ///< n [kg]
  Eigen::VectorXd node_areas;      ///< n [m^2], a third of each adjacent triangle
  sdk::Triangles triangles;
  std::vector<Spring> springs;  ///< structural springs first, then shear springs
  int structural_count = 0;
  std::vector<BendingStencil> bending;
  double bending_stiffness = 0.0;  ///< [N m]
  double bending_damping = 0.0;    ///< [N m s]
  double air_damping = 0.0;        ///< [kg/(m^2 s)]
  double surface_density = 0.0;    ///< [kg/m^2]

  int node_count() const { return static_cast<int>(masses.size()); }
};

/// Builds springs, bending stencils and lumped masses from a triangle mesh.
ClothModel build_cloth_model(const sdk::Positions& positions, const sdk::Triangles& triangles,
                             const ClothMaterial& material);

}  // namespace shellflow::cloth
