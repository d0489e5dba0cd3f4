#pragma once
// ShellSurface: what the fluid sees of a solid (§5: the solid is a black box that
// exposes triangle surfaces with node positions, velocities and surface density).

#include <Eigen/Core>
#include <memory>
#include <span>
#include <string>

namespace shellflow::sdk {

using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  ///< one node per row
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;     ///< node index triples
using TriangleVectors = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  ///< one vector per triangle

/// One thin shell as the fluid sees it at one instant. A value type: the runtime keeps
/// copies at times n, n+1 and n+2 (the topology is shared, never copied).
struct ShellSurface {
  std::string name;                            ///< "<solid instance>/<surface>", unique in a run
  std::shared_ptr<const Triangles> triangles;  ///< fixed for the whole run
  Positions positions;                         ///< world positions [m]
  Positions velocities;                        ///< node velocities [m/s]
  Eigen::VectorXd surface_density;             ///< per triangle [kg/m^2]
  bool receives_fluid_forces = false;          ///< two-way coupled (§5.1) or kinematic (one-way)

  int node_count() const { return static_cast<int>(positions.rows()); }
  int triangle_count() const { return triangles ? static_cast<int>(triangles->rows()) : 0; }
};

/// All shells of a run at one instant, in a fixed order (solid by solid, surface by surface).
using ShellSet = std::span<const ShellSurface>;

}  // namespace shellflow::sdk
