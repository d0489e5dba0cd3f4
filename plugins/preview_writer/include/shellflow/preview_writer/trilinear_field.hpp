#pragma once
// TrilinearField: one scalar grid field (sdk::FieldView, one component) seen by a ray
// caster: trilinear interpolation between samples, the value of the nearest border sample
// beyond the outer samples, and the box the field covers with a ray–box clip. Shared by
// SmokeVolume (density) and WaterSurface (level set).
//
// The box: cell-centred samples cover [origin - dx/2, origin + (dims - 1/2) dx], node
// samples [origin, origin + (dims - 1) dx].

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

class TrilinearField {
 public:
  /// A view of `field` (component 0); the field's data must outlive this object. `role`
  /// names the field in messages ("density", "level set").
  /// @throw std::invalid_argument when the field is not a non-empty scalar with dx > 0.
  TrilinearField(const sdk::FieldView& field, const std::string& role);

  /// Trilinear value at world point x, the coordinates clamped to the outer samples
  /// (constant beyond them, also outside the box).
  double value(const Eigen::Vector3d& x) const;
  /// x's cell (its lowest sample, clamped to the outer samples) and x's offsets in it.
  struct Stencil {
    int base[3];
    double w[3];
  };
  Stencil stencil(const Eigen::Vector3d& x) const;
  /// The trilinear value of a stencil (value(x) = value(stencil(x))).
  double value(const Stencil& st) const;
  /// The stencil's trilinear value with the samples that `seen(x, sample position)` rules
  /// out replaced by the mean of those it keeps (the simulation's stencil rule next to a
  /// shell, §4.4.1); `fallback` when it keeps none.
  double value_seen(const Stencil& st, const Eigen::Vector3d& x,
                    const std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)>& seen,
                    double fallback) const;
  /// The flat index of a stencil's cell among cells() (i + n0 (j + n1 k)).
  std::int64_t cell_index(const Stencil& st) const;
  /// Cells between samples along each axis (at least 1).
  std::array<int, 3> cells() const;
  /// Whether x lies in the box (faces included).
  bool contains(const Eigen::Vector3d& x) const;
  /// Ray parameters [s_in, s_out] where origin + s·direction is inside the box; false when
  /// the ray misses it. `entry_axis` (optional) receives the axis whose slab the ray
  /// enters last, i.e. the box face through which it enters at s_in (-1: none, the ray is
  /// parallel to every slab it starts in).
  bool clip(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double& s_in,
            double& s_out, int* entry_axis = nullptr) const;

  double dx() const { return m_dx; }
  /// Position of sample (0, 0, 0).
  const Eigen::Vector3d& origin() const { return m_origin; }
  const Eigen::Vector3d& lower() const { return m_lower; }
  const Eigen::Vector3d& upper() const { return m_upper; }

 private:
  const double* m_data = nullptr;
  std::array<int, 3> m_dims{0, 0, 0};
  Eigen::Vector3d m_origin = Eigen::Vector3d::Zero();
  double m_dx = 0.0;
  Eigen::Vector3d m_lower = Eigen::Vector3d::Zero();
  Eigen::Vector3d m_upper = Eigen::Vector3d::Zero();
};

}  // namespace shellflow::preview_writer
