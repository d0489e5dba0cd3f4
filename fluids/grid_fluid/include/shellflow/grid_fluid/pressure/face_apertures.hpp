#pragma once
// FaceApertures: the face fractions of a water scene's pressure solves near shells (Batty,
// Bertails & Bridson 2007, for the thin shells of §3). A solve treats a cell as all of the
// side of the shells its centre lies on. A shell that passes through the cell between its
// centre and a face's edge leaves that face only part of its square on the centre's side
// (ShellGeometry::face_apertures): without that, a plate a third of a cell above a plane of
// nodes passed water as if it lay on that plane, and water spreading on it sank into it.
// An open face of fraction β conducts β in the Laplacian (and β/θ to the air beyond it)
// and counts β u + (1 − β) u_shell in its cells' divergence.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "shellflow/geometry/shell_band.hpp"
#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/grid_fluid/mac/mac_grid.hpp"
#include "shellflow/grid_fluid/mac/shell_geometry.hpp"

namespace shellflow::grid_fluid {

class FaceApertures {
 public:
  struct Face {
    std::int64_t face;      ///< flat index in its family
    std::int64_t plus;      ///< the cell on its + side (it is that cell's min face)
    std::int64_t minus;     ///< the cell on its − side
    double fraction;        ///< β
    double shell_velocity;  ///< the shells' velocity there along the face's axis
  };

  /// The fractions of `shells` (ShellGeometry::face_apertures), with the velocity set on
  /// `shells` now (the projection's §4.3 effective velocity), leaving out the faces that
  /// `closed` flags per family (walls, sources: their velocity is held).
  void gather(const ShellGeometry& shells, const geometry::ShellBand& band,
              const std::array<std::vector<std::uint8_t>, 3>& closed);
  /// None: every face is whole.
  void clear();
  const std::vector<Face>& faces(int axis) const { return m_faces[axis]; }

  /// flux[c] (Σ over cell c's faces of u·n, one entry per cell) with each face here
  /// counted as β u + (1 − β) u_shell instead of u; `sign` −1 for −flux.
  void adjust_fluxes(const MacGrid& mac, Eigen::VectorXd& flux, double sign = 1.0) const;
  /// Scales the weights of family `axis` by β: `weights` lie over the faces of the box of
  /// cells of `grid` from `box_lo` (`face_counts` per axis, GridLaplacian::face_counts);
  /// faces outside the box are left out. The whole grid: box_lo 0, the grid's face counts.
  void scale_weights(int axis, const grid::UniformGrid& grid, const Eigen::Vector3i& box_lo,
                     const Eigen::Vector3i& face_counts, std::vector<float>& weights) const;

 private:
  std::array<std::vector<Face>, 3> m_faces;
};

}  // namespace shellflow::grid_fluid
