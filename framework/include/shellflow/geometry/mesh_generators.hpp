#pragma once
// Triangle meshes for shells: generators (plane/grid, box, open box, open cylinder,
// sphere), OBJ loading, and the scene-file form shared by every solid plugin:
//
//   "mesh": {"type": "grid", "width": 2, "height": 3, "nodes_u": 11, "nodes_v": 16,
//            "pattern": "herringbone"}
//   "mesh": {"type": "obj", "file": "meshes/cup.obj"}
//   "mesh": {"type": "file", "file": "meshes/hull.stl"}   (mesh_import.hpp: STL, PLY, glTF ...)
//   "transform": {"scale": 1, "rotate_axis": [0,1,0], "rotate_deg": 90, "translate": [2,4,3]}
//
// Conventions (tests rely on them):
//  - grid: in the x–y plane (normal +z), centred at the origin; node (i, j) has index
//    i + nodes_u * j, i along +x, j along +y; j = nodes_v-1 is the "top" edge.
//  - closed meshes (box, sphere) have outward normals (counter-clockwise seen from outside);
//    open_box and open_cylinder are cups open towards +y with outward normals.
//  - box, open_box: centred at the origin. open_cylinder: axis +y, base at y = 0.

#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shellflow/sdk/schema.hpp"
#include "shellflow/sdk/shell_surface.hpp"

namespace shellflow::geometry {

/// Where a mesh read from a file came from, so that check_mesh() can name the file, the
/// line and the vertex of a problem (null for generated meshes: they name node indices).
struct MeshOrigin {
  std::filesystem::path file;
  std::vector<int> vertex_number;  ///< per mesh node: its 1-based vertex number in the file
  std::vector<int> vertex_line;    ///< per mesh node: the line of its "v" (0: unknown)
  int unreferenced_count = 0;      ///< vertices of the file that no face uses (dropped)
  int first_unreferenced = 0;      ///< the 1-based number of the first of them
  int first_unreferenced_line = 0;
};

struct SurfaceMesh {
  sdk::Positions positions;
  sdk::Triangles triangles;
  std::shared_ptr<const MeshOrigin> origin;  ///< set by load_obj and load_mesh_file
};

/// A mesh of `nodes` and `triangles` (node indices) gathered in std::vectors, as the
/// generators and the file readers build them.
SurfaceMesh to_mesh(const std::vector<Eigen::Vector3d>& nodes,
                    const std::vector<std::array<int, 3>>& triangles);

/// How each grid quad is split into two triangles.
enum class GridPattern {
  Regular,      ///< every quad split along the same diagonal
  Herringbone,  ///< diagonal direction alternates from column to column (PhysBAM's cloth)
  Alternating,  ///< diagonal direction alternates in a checkerboard (isotropic-looking)
};

SurfaceMesh make_grid(double width, double height, int nodes_u, int nodes_v, GridPattern pattern);
SurfaceMesh make_box(const Eigen::Vector3d& size, int divisions);
SurfaceMesh make_open_box(const Eigen::Vector3d& size, int divisions);
SurfaceMesh make_open_cylinder(double radius, double height, int segments, int rings,
                               bool bottom_cap);
SurfaceMesh make_sphere(double radius, int subdivisions);
/// The surface swept by turning a profile polyline of (r, y) points (r ≥ 0, its distance
/// from the y axis) about +y: a goblet, a vase or a cup. The profile is resampled to
/// `rings` cells of equal arc length, its corners kept; `segments` nodes go round. A profile
/// point on the axis (r = 0) is one node: at an end it closes the surface (a cup's floor),
/// inside it joins two sheets there (a goblet's stem to its bowl). Normals face the side
/// to the right of the profile's direction (outwards for a profile going up the outside).
SurfaceMesh make_revolution(const std::vector<Eigen::Vector2d>& profile, int segments, int rings);
/// An open canoe-like hull along x, its gunwale (the open rim) in the plane y = 0 and its
/// keel below: half-beam b(u) = beam/2 · (1 − u²)^½ and depth d(u) = depth · (1 − u⁴)^½ at
/// station u = 2x/length ∈ [−1, 1], each section a superellipse of exponent `fullness`
/// (2: round, larger: flatter bottom and fuller sides), closing to a point at bow and stern.
/// `stations` cells along the length, `sections` cells round each section; outward normals.
SurfaceMesh make_boat_hull(double length, double beam, double depth, double fullness,
                           int stations, int sections);
/// Reads an OBJ file (tinyobjloader), triangulating polygons and dropping the vertices no
/// face uses (counted in the result's `origin` for check_mesh()). Throws IoError naming the
/// file, and the line and vertex for a coordinate that is not a finite number (tinyobjloader
/// would read "nan" as 0, so the "v" lines are scanned here first), for a face index out of
/// range and for a file without faces.
SurfaceMesh load_obj(const std::filesystem::path& file);

/// The "mesh" variant schema (one option per generator, plus "obj" and "file").
sdk::Schema mesh_schema();
/// Builds the mesh described by a validated "mesh" object (absent fields take the schema's
/// defaults). Throws ConfigError at `json_path` + "/<field>" for values the schema cannot
/// check, and at `json_path` + "/file" for a file load_obj() or load_mesh_file() refuses
/// (the message is theirs). The generators themselves throw std::invalid_argument for out-of-range
/// arguments. The mesh is not checked here: solids call check_mesh() after "transform".
SurfaceMesh make_mesh(const nlohmann::json& spec, const std::string& json_path = "/mesh");

/// The "transform" object schema: scale, then rotation about an axis, then translation.
sdk::Schema transform_schema();
/// Scale s, axis a, angle θ, translation t → x ↦ t + R(a, θ) s x. Absent fields (or a null
/// spec) take the defaults; a zero axis with θ ≠ 0 is a ConfigError at `json_path`.
Eigen::Affine3d transform_from_json(const nlohmann::json& spec,
                                    const std::string& json_path = "/transform");
void apply_transform(const Eigen::Affine3d& transform, SurfaceMesh& mesh);

}  // namespace shellflow::geometry
