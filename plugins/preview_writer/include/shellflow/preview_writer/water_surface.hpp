#pragma once
// WaterSurface: the water's level set seen by a ray caster. φ ≤ 0 is water, φ > 0 air
// (Guendelman et al. 2005 §4.4, after Enright et al. 2002), a signed distance near the
// surface sampled on the grid nodes; between samples φ is trilinear (TrilinearField).
//
// first_hit() finds the first crossing of φ = 0 along a ray segment, the classical
// ray-marched implicit surface: φ is sampled every h (h ≤ dx/2 keeps features of a cell
// or more from being stepped over); the first step ending in water (φ ≤ 0) brackets the
// crossing, which regula falsi with the Illinois modification (Dowell–Jarratt 1971)
// refines to |φ| ≤ 1e-9 dx or a bracket of 1e-9 dx. A sheet of water thinner than h
// between two samples can be missed. Outside the field's box there is no water: a ray
// whose entry point into the box is already in water hits the box face there (water
// against the domain wall), with that face's normal.
//
// The normal is ∇φ/|∇φ| with ∇φ by central differences of the trilinear φ with step dx,
// which equals the trilinear interpolant of the nodes' central differences: continuous
// across cells (the trilinear φ's own gradient jumps at cell faces and shades facets).

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "shellflow/preview_writer/shell_scene.hpp"
#include "shellflow/preview_writer/trilinear_field.hpp"
#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

struct WaterHit {
  double distance = std::numeric_limits<double>::infinity();  ///< ray parameter; inf: none
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();           ///< unit, towards the air
  bool hit() const { return distance < std::numeric_limits<double>::infinity(); }
};

class WaterSurface {
 public:
  /// A view of the level set `field` (one component); its data must outlive the surface.
  /// @throw std::invalid_argument when the field is not a non-empty scalar with dx > 0.
  explicit WaterSurface(const sdk::FieldView& field);

  /// Trilinear φ at x (coordinates clamped to the outer samples).
  double phi(const Eigen::Vector3d& x) const { return m_field.value(x); }
  /// ∇φ at x: central differences of the trilinear φ with step dx.
  Eigen::Vector3d gradient(const Eigen::Vector3d& x) const;

  /// The first point of origin + s·direction, s in [0, max_distance] and in the field's
  /// box, where φ ≤ 0, marching with step h [m] (h > 0); no hit when there is none.
  WaterHit first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                     double max_distance, double h) const;

  double dx() const { return m_field.dx(); }

  /// From now on, in the cells a triangle of `shells` may cut, φ is interpolated as the
  /// simulation does (§4.4.1): the nodes a shell hides from the point are replaced by the
  /// mean of those it sees (air, +dx, when it sees none). Plain trilinear φ carried water
  /// touching a wall up to half a cell past it, where it showed through the wall.
  /// `scene` must outlive the surface.
  void see_shells(const ShellScene& scene);

 private:
  /// φ at x: trilinear, or as see_shells() says in the cells next to a shell.
  double phi_seen(const Eigen::Vector3d& x) const;

  TrilinearField m_field;
  const ShellScene* m_scene = nullptr;
  std::vector<std::uint8_t> m_near_shell;  ///< per cell of m_field: a triangle's box meets it
};

}  // namespace shellflow::preview_writer
