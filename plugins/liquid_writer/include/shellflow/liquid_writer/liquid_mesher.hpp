#pragma once
// The water's surface as a triangle mesh with per-vertex velocity, from the fluid's level
// set φ (φ <= 0 water; "phi", §4.4) on the nodes or the cell centres, by OpenVDB's mesher
// (tools::VolumeToMesh: one vertex per cell with a sign change, a quad about each cell edge
// with one; with adaptivity > 0 flat regions merge into larger polygons). OpenVDB is not
// included here.
//
// Not bridging thin shells. A node holds one φ, and across a thin shell the two ends of
// a cell edge see different water (§3): a wet node beside the shell and a dry one behind
// it put the linear zero crossing anywhere between them, behind the shell as often as not,
// and the mesh would join the wet side to the dry side. So the mesh is made of
//     ψ = max(φ, τ) on the corners of the cells a shell touches (shell_cells.hpp) and on
//                   the nodes on the faces of the field's box,
//     ψ = φ         elsewhere,
// τ = 1e-3 Δx: just air. The water is the fluid's water less the cells the shells touch,
// cut at the box. With every corner of a touched cell dry, no touched cell has a sign
// change, so none holds a vertex, and every edge with a sign change lies outside them:
// each quad joins the vertices of the four cells about such an edge, a block that no shell
// touches, and lies inside it. Hence no triangle meets a shell. With adaptivity, the cells
// within two cells of a touched cell are kept from merging (VolumeToMesh's adaptivity
// mask), so that the cells next to shells keep their own vertices; the argument is the
// uniform mesh's, and the tests check adaptivity 0.5 and 1 on a plate and the dam.
// The water ends within a cell of each shell: the crossing next to a τ node lies at that
// node to within τ/|φ| of a cell, on the faces of the touched cells. On the box's faces
// the mesh closes: it is a closed surface.
//
// A cell-centred φ (Location::Cell) has its outermost samples half a cell inside the walls,
// and clipping them would erase the first layer of cells, the water lying on a floor. So
// the mesh is made on its samples inside one ghost layer, each ghost
//     g = max(−φ_b, τ),  φ_b the first cell's φ (its nearest sample):
// a wet first cell's φ mirrored (a linear φ through φ_b and −φ_b half a cell either side of
// the wall is zero on it), a dry one's air; only the ghosts are clipped, and the mesh
// closes on the walls as a node field's does on its box's faces.
// Smoothing (optional) filters φ first (OpenVDB LevelSetFilter, Gaussian), so it cannot
// undo the clipping. A cell field is filtered pass by pass inside ghost layers of φ_b
// (constant beyond the centres, as the simulation continues it): the air OpenVDB assumes
// beyond the samples would eat the water against the walls. A node field is filtered as it
// is, and loses the water along the box's faces (docs/known-limits.md).
//
// Error: a smooth closed surface of curvature radius R meshed at Δx ≪ R from its exact
// signed distance: the edge crossings lie on it to O(Δx²/R), a vertex (their mean) inside
// it by about 0.4Δx²/R; area and enclosed volume are short by O((Δx/R)²) relative
// (liquid_mesher_test: 0.6 and 1.1 (Δx/R)² for a sphere). Edges and corners of the water
// are bevelled by about a cell.

#include <cstdint>

#include "shellflow/sdk/fluid_solver.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::liquid_writer {

struct LiquidMeshOptions {
  double adaptivity = 0.0;       ///< OpenVDB's threshold in [0, 1]: 0 uniform, 1 the most merging
  int smoothing_iterations = 0;  ///< Gaussian filter passes over φ before meshing (0: none)
};

struct LiquidMesh {
  sdk::Positions positions;        ///< [m]
  sdk::Triangles triangles;        ///< counter-clockwise seen from the air (normals point out)
  sdk::Positions velocities;       ///< [m/s] per vertex; zero rows when no velocity was given
  std::int64_t clipped_nodes = 0;  ///< samples whose φ <= 0 was made τ (next to shells, box)
};

/// Meshes `phi` (a one-component node or cell field) with per-vertex velocity trilinear in
/// `velocity` (a three-component field, or null; for a node φ on the same nodes, for a cell
/// φ any grid: sampled at the vertices' positions, clamped to its box), never across a
/// triangle of `shells`. @throw Error when phi is not a non-empty one-component field with
/// dx > 0 or velocity is not a three-component field (on φ's nodes for a node φ).
LiquidMesh mesh_liquid(const sdk::FieldView& phi, const sdk::FieldView* velocity,
                       sdk::ShellSet shells, const LiquidMeshOptions& options);

/// Enclosed volume Σ a·(b×c)/6 and area of a closed triangle mesh (positive volume when the
/// triangles wind counter-clockwise seen from outside).
double mesh_volume(const sdk::Positions& positions, const sdk::Triangles& triangles);
double mesh_area(const sdk::Positions& positions, const sdk::Triangles& triangles);

}  // namespace shellflow::liquid_writer
