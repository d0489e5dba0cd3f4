#pragma once
// WaterSource: an emitter of water (the paper's streams, §7; PhysBAM's source boxes and
// cylinders): a sphere, box or cylinder inside which, while it is on, φ is set to the
// emitter's signed distance wherever that is smaller (the union of the water with the
// emitter) and whose velocity is held on the faces of its cells in every pressure solve.
// Its cells are sealed (every face held), so the volume it adds is its own: a nozzle fed
// from outside the domain. The shape, timing and held faces are those of SmokeSource.

#include <nlohmann/json.hpp>
#include <string>

#include "shellflow/grid_fluid/smoke/smoke_source.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"

namespace shellflow::grid_fluid {

class WaterSource {
 public:
  WaterSource(const nlohmann::json& spec, const std::string& json_path)
      : m_emitter(spec, json_path) {}
  static sdk::Schema schema() { return SmokeSource::schema(false); }

  bool active(double t) const { return m_emitter.active(t); }
  const std::optional<Eigen::Vector3d>& velocity() const { return m_emitter.velocity(); }
  /// φ = min(φ, signed distance to the emitter) on the level set's samples (its lattice's
  /// nodes: the MAC nodes, or the cell centres) within its band of it, while on at time t.
  /// Returns the samples inside.
  std::int64_t apply(double t, LevelSet& level_set) const;
  /// The nodes in the emitter's bounding box grown by `margin` [m].
  grid::IndexBox bounding_nodes(const grid::UniformGrid& grid, double margin) const {
    return m_emitter.bounding_samples(grid, grid::Location::Node, margin);
  }
  /// @throw ConfigError at `json_path` when the emitter shares no volume with the domain
  /// (SmokeSource::require_in_domain): it would never add water.
  void require_in_domain(const grid::UniformGrid& grid, const std::string& json_path) const {
    m_emitter.require_in_domain(grid, json_path, "it would never add water");
  }
  /// The signed distance from p to the emitter's shape [m] (negative inside).
  double signed_distance(const Eigen::Vector3d& p) const { return m_emitter.signed_distance(p); }
  /// The emitter shape's bounding box.
  Eigen::AlignedBox3d bounds() const { return m_emitter.bounds(); }
  /// Does the emitter's shape contain p?
  bool contains(const Eigen::Vector3d& p) const { return m_emitter.contains(p); }
  /// The cells whose centre may lie inside it (clamped to the grid).
  grid::IndexBox bounding_cells(const grid::UniformGrid& grid) const {
    return m_emitter.bounding_samples(grid, grid::Location::Cell, 0.0);
  }
  /// The held faces of family `axis` (SmokeSource::append_faces with a closed intake).
  void append_faces(double t, const grid::UniformGrid& grid, int axis,
                    std::vector<SourceFace>& out) const {
    m_emitter.append_faces(t, grid, axis, true, out);
  }

 private:
  SmokeSource m_emitter;
};

}  // namespace shellflow::grid_fluid
