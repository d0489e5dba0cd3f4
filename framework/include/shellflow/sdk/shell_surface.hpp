#pragma once
// ShellSurface: what the fluid sees of a solid (§5: the solid is a black box that
// exposes triangle surfaces with node positions, velocities and surface density).

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace shellflow::sdk {

using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  ///< one node per row
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;     ///< node index triples
using TriangleVectors = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  ///< one vector per triangle

/// A shell that moves as one rigid body, at the instant of its ShellSurface. Given, the
/// fluid solves the body's motion together with its coupling pressure (the body's faces
/// are not each given the density σ/Δx of §5.1, which lets a hull's walls yield to the
/// water one by one: an open boat would sink, its hull draining in the solve).
struct RigidBody {
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();  ///< world [m]
  /// [1/kg]: identity / mass for a free body; a locked direction has a zero row and column.
  Eigen::Matrix3d inverse_mass = Eigen::Matrix3d::Zero();
  /// [1/(kg m^2)]: world frame, about the centre of mass; zero for locked rotations.
  Eigen::Matrix3d inverse_inertia = Eigen::Matrix3d::Zero();
  /// [m/s^2]: what the solid adds to the body's velocity over its next step besides the
  /// fluid's forces (its gravity), so the pressure can balance it (Archimedes, in water).
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
};

/// One thin shell as the fluid sees it at one instant. A value type: the runtime keeps
/// copies at times n, n+1 and n+2 (the topology is shared, never copied).
struct ShellSurface {
  std::string name;                            ///< "<solid instance>/<surface>", unique in a run
  std::shared_ptr<const Triangles> triangles;  ///< fixed for the whole run
  Positions positions;                         ///< world positions [m]
  Positions velocities;                        ///< node velocities [m/s]
  Eigen::VectorXd surface_density;             ///< per triangle [kg/m^2]
  bool receives_fluid_forces = false;          ///< two-way coupled (§5.1) or kinematic (one-way)
  std::optional<RigidBody> rigid;              ///< two-way shells that move as one rigid body

  int node_count() const { return static_cast<int>(positions.rows()); }
  int triangle_count() const { return triangles ? static_cast<int>(triangles->rows()) : 0; }
};

/// All shells of a run at one instant, in a fixed order (solid by solid, surface by surface).
using ShellSet = std::span<const ShellSurface>;

}  // namespace shellflow::sdk
