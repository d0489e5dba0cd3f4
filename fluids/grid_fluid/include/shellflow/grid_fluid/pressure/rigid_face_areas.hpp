#pragma once
// The part of a rigid shell that each of its coupling faces stands for.
//
// A face f of axis a that the shell cuts (between two cell centres, Fig. 5) reads the
// pressure jump there; in the solve it carries the body's push on the fluid, and the body
// takes the jump's force. With a whole face per cut and the force along e_a alone (a
// staircase), the area and its centroid are off, and a heeled box loses the vertical part
// of the water's push on its walls, a couple that turns its righting moment the wrong way.
//
// Here the shell's triangles are cut into the grid's cells and each piece goes to one face:
// of the axis its normal is closest to, the cut of its own column across that axis nearest
// to it on the same sheet (the cut triangle facing within 45° of it and the piece within Δx
// of its plane), else one in the eight columns beside (a rim the column's centre line
// misses), else the nearest cut on its sheet, of any axis: no piece is left out, so that a
// closed shell's inside, at one pressure, pushes on it with no net force. A face then stands
// for its pieces whole:
//     N_f = Σ n A,   M_f = Σ (c − x_cm) × n A,   Φ_f = Σ (u(c)·n) A,
// n the unit normal turned to the face's + side (as the cut triangle's), c and u(c) a piece's centroid and the shell's
// velocity there. J_f = [N_f; M_f]/Δx² replaces [e_a; r × e_a]: the force −[p] N_f and its
// moment act where the pieces are, and the fluid's flux through the face, Φ_f + N_f·a Δt
// for a body of acceleration a, is the volume the pieces sweep. Σ_f N_f is the shell's
// vector area, so Archimedes holds at any heel.

#include <Eigen/Core>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::grid_fluid {

/// One face of a rigid body's cut: its axis, its face index triple, where the shell
/// crosses the segment between its cells' centres and the triangle crossed there.
struct RigidFaceCut {
  int axis = 0;
  Eigen::Vector3i face = Eigen::Vector3i::Zero();
  double crossing = 0.0;  ///< [m], the coordinate along `axis`
  int triangle = -1;
};

/// What a face stands for (zero where no piece came to it).
struct RigidFacePieces {
  Eigen::Vector3d vector_area = Eigen::Vector3d::Zero();  ///< N_f [m²]
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();       ///< M_f about the centre of mass [m³]
  double flux = 0.0;                                      ///< Φ_f [m³/s]
};

/// The pieces of `shell` (in `grid`'s cells; parts outside them are left) for each of
/// `cuts`, moments about `centre_of_mass`.
std::vector<RigidFacePieces> rigid_face_pieces(const grid::UniformGrid& grid,
                                               const sdk::ShellSurface& shell,
                                               const Eigen::Vector3d& centre_of_mass,
                                               const std::vector<RigidFaceCut>& cuts);

}  // namespace shellflow::grid_fluid
