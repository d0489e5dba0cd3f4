#pragma once
// SmokeSource: an emitter of smoke (§4.1, Fedkiw, Stam, Jensen 2001): a sphere, a box or a
// cylinder inside which, while it is on, the node density (and temperature) are set to the
// emitter's values. Its velocity is held on the MAC faces of its cells, those whose centres
// lie inside (Neumann in every pressure solve, as PhysBAM's source faces), not set on the
// nodes: §4.2's increments from nodes reset every step would leak onto the free faces about
// its rim. Where the domain has an open side, the faces through which the velocity would
// flow into the emitter (its intake) carry none: the emitter adds its volume, a nozzle fed
// by a pipe from outside the domain. A nozzle that drew its air from around its back made
// the flow about the intake rim climb past 1.7x the jet's speed within 0.2 s of the paper's
// curtain scene, and the CFL step shrink with it.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "shellflow/grid_fluid/mac/domain_boundary.hpp"
#include "shellflow/grid_fluid/mac/node_fields.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

class SmokeSource {
 public:
  enum class Shape { Sphere, Box, Cylinder };

  /// From one validated entry of "sources" (schema()); ConfigError at `json_path`/...
  SmokeSource(const nlohmann::json& spec, const std::string& json_path);
  /// The "sources" entry; with `smoke` false, the same emitter without density and
  /// temperature (a water emitter, WaterSource).
  static sdk::Schema schema(bool smoke = true);

  /// Is the emitter on at time t (start <= t < end)?
  bool active(double t) const { return t >= m_start && t < m_end; }
  bool contains(const Eigen::Vector3d& p) const;
  /// Signed distance [m] from p to the emitter's surface (negative inside).
  double signed_distance(const Eigen::Vector3d& p) const;
  /// The emitter's bounding box (a cylinder's: its axis grown by the radius every way).
  Eigen::AlignedBox3d bounds() const;
  /// @throw ConfigError at `json_path` (as outside_domain()) when the emitter shares no
  /// volume with `grid`'s domain; `consequence` says what it would then never do. Exact for
  /// a sphere and a box; a cylinder is judged by bounds(), which may pass one that only
  /// passes by an edge of the domain.
  void require_in_domain(const grid::UniformGrid& grid, const std::string& json_path,
                         const std::string& consequence) const;
  /// The samples at `loc` in the emitter's bounding box grown by `margin` [m].
  grid::IndexBox bounding_samples(const grid::UniformGrid& grid, grid::Location loc,
                                  double margin = 0.0) const;
  /// Sets the emitter's values on every node inside it (no-op when off at time t).
  /// Returns the number of nodes set.
  std::int64_t apply(double t, const grid::UniformGrid& grid, NodeFields& fields,
                     bool temperature) const;

  /// Appends the faces of family `axis` of the emitter's cells (the cells whose centres lie
  /// inside) with the emitter's velocity: none when off at time t or without a velocity.
  /// With `closed_intake`, the faces through which that velocity would flow into the
  /// emitter get no normal velocity instead. Every emitter cell is then sealed (all its
  /// faces held), so the volume it adds is its own, not drawn from its neighbours.
  void append_faces(double t, const grid::UniformGrid& grid, int axis, bool closed_intake,
                    std::vector<SourceFace>& out) const;

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
