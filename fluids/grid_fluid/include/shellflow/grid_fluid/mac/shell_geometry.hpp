#pragma once
// ShellGeometry: the thin shells at one instant as the fluid queries them (§3): owned
// copies of the node positions and velocities (the runtime's ShellSet only lives for one
// call), one TriangleBvh per shell and one WedgeCaster over all of them. Answers
// "is b visible from a" and "what is the object velocity where [a, b] meets a shell".

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/geometry/triangle_bvh.hpp"
#include "shellflow/geometry/wedge_caster.hpp"
#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::grid_fluid {

/// The point of the shells nearest to a query point, as a particle collides with it.
struct ShellContact {
  double distance = 0.0;                          ///< from the query point
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< on the surface
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit, towards the query's side
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< the object's velocity there
  bool on_open_edge = false;  ///< the point lies on an edge with one triangle (a rim, a hem)
  geometry::WedgeHit where;   ///< its shell, triangle and barycentric coordinates
};

/// A face of the MAC grid whose segment between its two cell centres meets a shell (Fig. 5).
struct CellFaceHit {
  std::int64_t face;       ///< flat index in its family (UniformGrid layout)
  geometry::WedgeHit hit;  ///< where the segment first meets a wedge (thickness ε)
};

/// An open face of the MAC grid near a shell, with the share of its area that the flow on
/// its cell centres' side of the shells passes (the pressure solves' face fraction).
struct FaceAperture {
  std::int64_t face;       ///< flat index in its family (UniformGrid layout)
  double fraction;         ///< open_square_fraction() of the nearest shell's plane
  geometry::WedgeHit hit;  ///< the nearest shell point
};

/// The open area over Δx² of a face cut by a plane: in the face's plane, with the face's
/// centre at the origin and lengths in Δx, the part of the square [−½, ½]² where
/// m1 s + m2 t + offset >= 0 (offset >= 0: the centre's side). 1 for a plane parallel to
/// the face (m1 = m2 = 0); ½ + h for a plate at a distance h <= ½ from the centre that
/// parallels one of the face's axes.
double open_square_fraction(double m1, double m2, double offset);

class ShellGeometry {
 public:
  /// No shells: everything is visible.
  ShellGeometry() = default;
  /// Copies `shells` and builds the hierarchies; `epsilon` is the wedge thickness ε.
  ShellGeometry(sdk::ShellSet shells, double epsilon);

  bool empty() const { return m_shells.empty(); }
  int shell_count() const { return static_cast<int>(m_shells.size()); }
  double epsilon() const { return m_epsilon; }
  const geometry::WedgeCaster& caster() const { return *m_caster; }
  const geometry::TriangleMesh& mesh(int s) const { return m_shells[s]->mesh; }
  const geometry::TriangleBvh& bvh(int s) const { return m_shells[s]->bvh; }

  /// True when `shells` has the same node positions as this copy (bit for bit).
  bool same_positions(sdk::ShellSet shells) const;

  /// Replaces the object velocities (`velocities[s]` for ShellSet entry s, one row per node), e.g.
  /// by the §4.3 effective velocity; an empty matrix keeps the shell's own velocities.
  void set_velocities(std::span<const sdk::Positions> velocities);

  /// Segment [a, b] touches no wedge of thickness `epsilon` (ε by default).
  bool visible(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    return m_shells.empty() || !m_caster->blocked(a, b);
  }
  bool visible(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double epsilon) const {
    return m_shells.empty() || !m_caster->blocked(a, b, epsilon);
  }
  /// The axis neighbours node `ijk` of `grid` cannot see: bit 2a + side (side 0: −, 1: +)
  /// set when the ray to the neighbour along axis a meets a shell; neighbours outside the
  /// grid are never set.
  std::uint8_t hidden_axis_neighbours(const grid::UniformGrid& grid,
                                      const Eigen::Vector3i& ijk) const;

  /// The object velocity (barycentric interpolation of node velocities) where [a, b]
  /// first meets a wedge of thickness ε; the velocity of the surface point closest to b
  /// when the segment meets none (b lies in no wedge then, so this is a fallback only).
  Eigen::Vector3d object_velocity(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
  /// The nearest surface point to p within `reach`, or none. Its normal points from the
  /// surface to p (the unit distance gradient); where p lies on the surface within round-off,
  /// the triangle's normal turned towards `side` (a point known to be on p's side, e.g. where
  /// p came from) stands in.
  std::optional<ShellContact> nearest(const Eigen::Vector3d& p, double reach,
                                      const Eigen::Vector3d& side) const;
  /// The velocity at a hit.
  Eigen::Vector3d velocity_at(const geometry::WedgeHit& hit) const;
  /// Where the material point of a hit (its triangle and barycentric coordinates) is in
  /// these shells; none when they have no such triangle (a shell with another topology).
  std::optional<Eigen::Vector3d> point_at(const geometry::WedgeHit& hit) const;
  /// The wedge [a, b] meets first (thickness ε), or none; hit.shell is an internal index.
  std::optional<geometry::WedgeHit> first_hit(const Eigen::Vector3d& a,
                                              const Eigen::Vector3d& b) const {
    if (m_shells.empty()) return std::nullopt;
    return m_caster->first_hit(a, b);
  }
  /// The interior faces of each family that the shells cut (Fig. 5), in face order: both
  /// pressure solves close or couple exactly these. Cast once per geometry (it is rebuilt
  /// whenever the shells move) over the faces `band` samples, which must hold every face
  /// within Δx/2 of a shell; later calls return the same lists whatever band they pass.
  const std::array<std::vector<CellFaceHit>, 3>& cell_face_hits(
      const geometry::ShellBand& band) const;
  /// The open interior faces of each family whose fraction (FaceAperture) is not 1, in
  /// face order: the plane of the shell point nearest the face's centre (within Δx/√2,
  /// not on an open edge, not on a two-way rigid body) cuts its square. Found once per
  /// geometry, like cell_face_hits(), over the faces `band` samples, which must hold every
  /// face within Δx/√2 of a shell.
  const std::array<std::vector<FaceAperture>, 3>& face_apertures(
      const geometry::ShellBand& band) const;
  /// Whether internal shell `shell` is two-way coupled (ShellSurface::receives_fluid_forces).
  bool receives_forces(int shell) const { return m_shells[shell]->receives_forces; }
  /// Whether internal shell `shell` is a two-way shell that moves as one rigid body.
  bool moves_as_one(int shell) const { return m_shells[shell]->moves_as_one; }
  /// Surface density [kg/m^2] of the triangle at a hit.
  double surface_density_at(const geometry::WedgeHit& hit) const;
  /// ShellSet position of internal shell `shell`.
  int set_index(int shell) const { return m_shells[shell]->set_index; }

  /// The last point of [a, b] from which a is reached without touching a wedge of
  /// thickness `epsilon` (b itself when the segment is clear; a when a is inside one).
  /// Bisection to 2^-10 of the segment (§4.1: the clipped semi-Lagrangian ray; the ray is
  /// at most a few Δx long, so the base point is placed to ~1e-3 Δx).
  Eigen::Vector3d clip(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double epsilon) const;

 private:
  struct Shell {
    sdk::Positions positions;
    sdk::Positions velocities;
    std::shared_ptr<const sdk::Triangles> triangles;
    Eigen::VectorXd surface_density;  ///< per triangle [kg/m^2]
    bool receives_forces = false;
    bool moves_as_one = false;  ///< two-way and rigid (ShellSurface::rigid)
    int set_index = -1;
    geometry::TriangleMesh mesh;
    geometry::TriangleBvh bvh;
    // The open boundary, found on the first nearest() that needs it (smoke never does):
    // per triangle, bit k for the edge opposite corner k; per node, on any open edge.
    mutable std::once_flag open_once;
    mutable std::vector<std::uint8_t> open_edges, open_nodes;
  };
  /// Whether a point of shell s's triangle t with these barycentrics lies on its open
  /// boundary (an edge one triangle has, or a node on such an edge).
  bool on_open_edge(int s, int t, const Eigen::Vector3d& barycentric) const;
  std::vector<std::unique_ptr<Shell>> m_shells;
  std::unique_ptr<geometry::WedgeCaster> m_caster;
  std::vector<int> m_internal;  ///< ShellSet position -> index in m_shells (-1: empty shell)
  mutable std::optional<std::array<std::vector<CellFaceHit>, 3>> m_cell_face_hits;
  mutable std::optional<std::array<std::vector<FaceAperture>, 3>> m_face_apertures;
  double m_epsilon = 0.0;
};

}  // namespace shellflow::grid_fluid
