#pragma once
// FaceNodeTransfer: the mixed node/face scheme of §4.2 (Guendelman et al. 2005).
//  - faces_to_nodes: component a of the velocity at a node is the average of the (up to)
//    four faces of family a around it, using only faces *visible* from the node; with no
//    visible face, the average of the object velocities where the rays met the shell.
//  - increments_to_faces: the node increments Δu = u* − u^n are averaged back to each face
//    from its four nodes, using only visible nodes, and added to the persistent face
//    velocity; with no visible node the face takes the object velocity instead.
// Faces swept by a moving shell (§3) carry values from the other side: they take the
// average of the visible nodes' u* (refilled, already valid) instead of an increment.
// A node that touches a source's held face carries the source's velocity, not the
// fluid's: its increment would leak the jet into the free faces about the emitter's rim
// every step (a nozzle's back rim spun up past 1.2x the jet in 0.2 s), so free faces take
// the increments of their other nodes only.
// Ray casts happen only for samples in the shell band; elsewhere the plain averages run.
// With cut cells (issue #52, docs/cut-cells.md §2.8) each fragment of a split face is a face
// sample of its own: a node reads the fragment that holds it as a corner (no ray: the
// corners' groups say what it sees), and a fragment takes the increments of its own corners.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid_fluid/mac/cell_parts.hpp"
#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {

/// The split faces of cut cells and their fragments' velocities, which the transfers read and
/// write beside the MAC's faces.
struct CutFaces {
  const CellParts* parts = nullptr;
  FragmentVelocities* velocities = nullptr;
};

class FaceNodeTransfer {
 public:
  explicit FaceNodeTransfer(const grid::UniformGrid& grid) : m_grid(grid) {}

  /// Node velocities from the face velocities (§4.2). `band` may be null (no shells).
  void faces_to_nodes(const MacGrid& mac, NodeFields& nodes, const ShellGeometry& shells,
                      const geometry::ShellBand* band, const CutFaces* cut = nullptr) const;

  /// Adds the averaged increments u* − u^n to the faces (§4.2). `node_valid_before[i]` is
  /// 0 for nodes that were swept this step (their increment is meaningless and is not
  /// used); `face_swept[a]` flags faces of family a swept by the shells (may be empty).
  /// Faces fixed by a wall or inflow condition are left alone; source faces are the
  /// caller's to set (apply_boundary_velocities).
  void increments_to_faces(MacGrid& mac, const NodeFields& u_star,
                           const std::array<std::vector<double>, 3>& u_n,
                           std::span<const std::uint8_t> node_valid_before,
                           const std::array<std::vector<std::uint8_t>, 3>& face_swept,
                           const ShellGeometry& shells, const geometry::ShellBand* band,
                           const DomainBoundary& boundary, const CutFaces* cut = nullptr);

 private:
  /// The nodes touching a held source face of one family, flagged, and the box of the
  /// faces of that family that have such a node as a corner (empty: none).
  struct HeldNodes {
    std::vector<std::uint8_t> flag;     ///< per node; allocated with the first source
    std::vector<std::int64_t> flagged;  ///< to clear them cheaply next step
    grid::IndexBox faces{Eigen::Vector3i::Zero(), -Eigen::Vector3i::Ones()};
  };
  void mark_held_nodes(const DomainBoundary& boundary, int axis);

  /// faces_to_nodes for one node in the shell band: rays decide which faces it sees.
  void faces_to_nodes_with_rays(const MacGrid& mac, NodeFields& nodes, const ShellGeometry& shells,
                                std::int64_t node, const CutFaces* cut) const;
  /// increments_to_faces for the fragments of the split faces of family `axis`.
  void increments_to_fragments(int axis, MacGrid& mac, const NodeFields& u_star,
                               const std::vector<double>& u_n,
                               std::span<const std::uint8_t> node_valid_before,
                               const std::vector<std::uint8_t>& face_swept,
                               const CutFaces& cut) const;

  grid::UniformGrid m_grid;
  std::array<HeldNodes, 3> m_held;
};

/// Sets the wall (0) and inflow (given) normal velocities on the domain faces.
void apply_boundary_velocities(MacGrid& mac, const DomainBoundary& boundary);
/// Is face `ijk` of family `axis` on the domain boundary with a fixed (wall or inflow)
/// normal velocity?
bool fixed_boundary_face(const grid::UniformGrid& grid, const DomainBoundary& boundary, int axis,
                         const Eigen::Vector3i& ijk);

}  // namespace shellflow::grid_fluid
