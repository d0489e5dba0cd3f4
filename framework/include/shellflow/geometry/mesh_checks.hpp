#pragma once
// Checks of a shell mesh as a solid is about to use it (read or generated, after its
// "transform"), in one place for every solid plugin. Each solid states in a MeshCheckPolicy
// which defects it cannot simulate (errors) and which it copes with (warnings with counts),
// and why, next to its call of check_mesh().
//
// Always errors, whatever the policy: a node position that is not finite (an OBJ "nan" is
// refused earlier by load_obj with its line; here a transform that overflows), a triangle
// index out of range, and a mesh without triangles.
//
// Messages name the mesh's file, each vertex by its 1-based number in the file and the line
// of its "v" statement (see MeshOrigin); a generated mesh names node indices (0-based, as
// "pins" and "indices" count them).

#include <string>
#include <vector>

#include "shellflow/geometry/mesh_generators.hpp"

namespace shellflow::geometry {

enum class MeshCheckSeverity {
  Warning,  ///< logged with its count; the mesh is used as it is
  Error,    ///< ConfigError naming the first offender
};

/// What a solid does with each kind of defect.
struct MeshCheckPolicy {
  /// Triangles of (numerically) zero area: a repeated corner, or three collinear corners
  /// (|(b - a) × (c - a)| ≤ kDegenerateRatio · (longest edge)²).
  MeshCheckSeverity degenerate_triangles = MeshCheckSeverity::Error;
  /// Vertices no triangle uses (load_obj drops them, which renumbers the later ones).
  MeshCheckSeverity unreferenced_vertices = MeshCheckSeverity::Warning;
  /// Edges shared by more than two triangles (not a manifold surface there).
  MeshCheckSeverity non_manifold_edges = MeshCheckSeverity::Error;
};

/// Twice a triangle's area over its longest edge squared, below which it counts as zero
/// area: 1e-12 is a few thousand ulps of the corners' relative round-off (2.2e-16), so a
/// triangle flagged has corners collinear to round-off, not merely a thin sliver.
inline constexpr double kDegenerateRatio = 1e-12;

/// Counts of what check_mesh() found, whatever their severity.
struct MeshCheckReport {
  int degenerate_triangles = 0;
  int unreferenced_vertices = 0;
  int non_manifold_edges = 0;
  /// One line per kind found at Warning severity (also logged through spdlog).
  std::vector<std::string> warnings;
};

/// Checks `mesh` against `policy`. `json_path` is where the mesh is described in the
/// plugin's parameters ("/mesh", "/bodies/0/mesh"); errors about a file's content point at
/// its "/file". `owner` starts each warning (e.g. the plugin instance's name).
/// @throw ConfigError naming the file, the line and the vertices (or the node indices) of
///        the first offender of every kind found at Error severity, with its count.
MeshCheckReport check_mesh(const SurfaceMesh& mesh, const MeshCheckPolicy& policy,
                           const std::string& json_path, const std::string& owner = "");

}  // namespace shellflow::geometry
