#pragma once
// SmokeSource: an emitter of smoke (§4.1, Fedkiw, Stam, Jensen 2001): a sphere or a box
// inside which, while it is on, the node density (and temperature, and velocity where
// given) are set to the emitter's values.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "shellflow/grid_fluid/node_fields.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

class SmokeSource {
 public:
  enum class Shape { Sphere, Box, Cylinder };

  /// From one validated entry of "sources" (schema()); ConfigError at `json_path`/...
  SmokeSource(const nlohmann::json& spec, const std::string& json_path);
  static sdk::Schema schema();

  /// Is the emitter on at time t (start <= t < end)?
  bool active(double t) const { return t >= m_start && t < m_end; }
  bool contains(const Eigen::Vector3d& p) const;
  /// Sets the emitter's values on every node inside it (no-op when off at time t).
  /// Returns the number of nodes set.
  std::int64_t apply(double t, const grid::UniformGrid& grid, NodeFields& fields,
                     bool temperature) const;

  const std::optional<Eigen::Vector3d>& velocity() const { return m_velocity; }
  const std::optional<double>& temperature() const { return m_temperature; }
  double density() const { return m_density; }

 private:
  Shape m_shape = Shape::Sphere;
  Eigen::Vector3d m_center = Eigen::Vector3d::Zero();
  double m_radius = 0.0;
  Eigen::Vector3d m_min = Eigen::Vector3d::Zero();  ///< box corner, or cylinder axis start
  Eigen::Vector3d m_max = Eigen::Vector3d::Zero();  ///< opposite corner, or axis end
  std::optional<Eigen::Vector3d> m_velocity;
  double m_density = 1.0;
  std::optional<double> m_temperature;
  double m_start = 0.0;
  double m_end = 0.0;
};

}  // namespace shellflow::grid_fluid
