#pragma once
// Triangle meshes from the files DCC tools write (the "file" mesh type):
//
//   "mesh": {"type": "file", "file": "meshes/hull.stl"}
//
// OBJ goes through load_obj(), whose errors name the line of a bad vertex. STL, PLY, glTF
// (.gltf, .glb), FBX, COLLADA (.dae), 3DS and the other formats assimp knows go through
// assimp: every mesh of the file, placed by its node transforms, polygons triangulated.

#include <filesystem>
#include <string>
#include <vector>

#include "shellflow/geometry/mesh_generators.hpp"

namespace shellflow::geometry {

/// Reads the triangle mesh of `file`, choosing the reader by the file's extension (.obj:
/// load_obj; any other format assimp supports: assimp). For assimp's formats, corners at
/// exactly the same position become one node (STL stores each triangle's corners apart, and
/// a texture seam splits a vertex in two: a cloth read as such would fall apart along them),
/// numbered in the order assimp reads them (a PLY's or glTF's own vertex order; an STL's
/// corners, three per triangle); points and lines in the file are left out with a warning.
/// Throws IoError naming the file: no such file, a format neither reader knows (listing the
/// common ones), a file the reader refuses (its message), a vertex with a coordinate that is
/// not a finite number (its number and the first triangle that uses it), or no triangles.
SurfaceMesh load_mesh_file(const std::filesystem::path& file);

/// The extensions load_mesh_file() reads, lower case with their dots (".obj" first).
std::vector<std::string> mesh_file_extensions();

}  // namespace shellflow::geometry
