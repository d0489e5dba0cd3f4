#pragma once
// DomainBoundary: the condition on each of the six faces of the domain box (§4.3):
//   Wall    Neumann, normal velocity 0 (free slip);
//   Open    outflow, Dirichlet p = 0 outside the face;
//   Inflow  Neumann, normal velocity given (the full given vector is imposed on the face's
//           normal component; tangential components enter through the node fields).
// Sides are numbered 2 * axis + (0 for the min face, 1 for the max face).
// Velocity sources add interior faces that behave like inflow faces (PhysBAM's psi_N source
// faces): the fluid sets them every step, and every pressure solve keeps their velocity.

#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/grid/uniform_grid.hpp"
#include "shellflow/sdk/schema.hpp"

namespace shellflow::grid_fluid {

enum class BoundaryType { Wall, Open, Inflow };

struct FaceCondition {
  BoundaryType type = BoundaryType::Wall;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< Inflow only [m/s]
};

/// An interior face whose velocity a source prescribes (flat index in the face layout).
struct SourceFace {
  std::int64_t face;
  Eigen::Vector3d velocity;
};

class DomainBoundary {
 public:
  static constexpr std::array<const char*, 6> kSideNames = {"x_min", "x_max", "y_min",
                                                            "y_max", "z_min", "z_max"};

  /// Every side a wall.
  DomainBoundary() = default;
  /// From a validated "boundary" object (schema()). Throws ConfigError at
  /// `json_path`/<side> for an inflow whose velocity points out of the domain.
  DomainBoundary(const nlohmann::json& spec, const std::string& json_path);

  static sdk::Schema schema();

  const FaceCondition& side(int axis, int max_side) const { return m_sides[2 * axis + max_side]; }
  FaceCondition& side(int axis, int max_side) { return m_sides[2 * axis + max_side]; }
  /// Does any side let fluid out (an open side)? Without one, the whole domain is an
  /// enclosed region that needs the §4.3 compatibility correction.
  bool has_open_side() const;

  /// The faces of family `axis` inside the sources that are on now (replaces the last set).
  void set_source_faces(int axis, std::vector<SourceFace> faces) {
    m_source_faces[axis] = std::move(faces);
  }
  const std::vector<SourceFace>& source_faces(int axis) const { return m_source_faces[axis]; }
  /// Does a source prescribe interior faces? They may cut the domain into regions.
  bool has_source_faces() const {
    return !m_source_faces[0].empty() || !m_source_faces[1].empty() ||
           !m_source_faces[2].empty();
  }

  /// Calls f(face, condition) for every face of family `axis` (flat index in
  /// grid::UniformGrid's face layout) on a wall or inflow side of `grid`'s box, then for
  /// every source face (as an inflow): the faces that are Neumann in every pressure solve
  /// (§4.3, §5.1).
  template <class F>
  void for_each_closed_face(const grid::UniformGrid& grid, int axis, F&& f) const {
    const auto loc = static_cast<grid::Location>(static_cast<int>(grid::Location::FaceX) + axis);
    const Eigen::Vector3i n = grid.counts(loc);
    const int b = (axis + 1) % 3;
    const int c = (axis + 2) % 3;
    for (int max_side = 0; max_side < 2; ++max_side) {
      const FaceCondition& condition = side(axis, max_side);
      if (condition.type == BoundaryType::Open) continue;
      Eigen::Vector3i ijk;
      ijk[axis] = max_side == 0 ? 0 : grid.cells()[axis];
      for (ijk[c] = 0; ijk[c] < n[c]; ++ijk[c])
        for (ijk[b] = 0; ijk[b] < n[b]; ++ijk[b]) f(grid.index(loc, ijk), condition);
    }
    for (const SourceFace& s : m_source_faces[axis])
      f(s.face, FaceCondition{BoundaryType::Inflow, s.velocity});
  }

 private:
  std::array<FaceCondition, 6> m_sides;
  std::array<std::vector<SourceFace>, 3> m_source_faces;
};

}  // namespace shellflow::grid_fluid
