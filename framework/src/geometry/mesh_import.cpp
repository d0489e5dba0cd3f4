#include "shellflow/geometry/mesh_import.hpp"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>

#include "shellflow/sdk/error.hpp"

namespace shellflow::geometry {

namespace {

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Frees assimp's scene when the import leaves this scope (also on a throw).
struct SceneRelease {
  void operator()(const aiScene* scene) const { aiReleaseImport(scene); }
};

/// Reads `file` through assimp. Node transforms are applied (PreTransformVertices), so that
/// a glTF's parts lie where the artist placed them; nothing else changes the geometry (no
/// degenerate-triangle removal: check_mesh() reports those as each solid decides).
SurfaceMesh import_with_assimp(const std::filesystem::path& file) {
  const unsigned flags =
      aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;
  std::unique_ptr<const aiScene, SceneRelease> scene(aiImportFile(file.string().c_str(), flags));
  if (!scene) throw IoError(file.string() + ": cannot read the mesh file: " + aiGetErrorString());

  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 3>> triangles;
  auto origin = std::make_shared<MeshOrigin>();
  origin->file = file;
  // Corners at exactly the same position are one node (see the header).
  std::map<std::array<double, 3>, int> node_at;
  int vertex_base = 0, skipped_primitives = 0, unused = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& mesh = *scene->mMeshes[m];
    std::vector<int> node_of(mesh.mNumVertices, -1);
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) {  // a point or a line (polygons were triangulated)
        ++skipped_primitives;
        continue;
      }
      std::array<int, 3> triangle{};
      const int number = static_cast<int>(triangles.size()) + 1;
      for (int c = 0; c < 3; ++c) {
        const unsigned v = face.mIndices[c];
        if (v >= mesh.mNumVertices)
          throw IoError(file.string() + ": triangle " + std::to_string(number) +
                        " refers to vertex " + std::to_string(vertex_base + v + 1) +
                        ", which the file does not have");
        if (node_of[v] < 0) {
          const aiVector3D& p = mesh.mVertices[v];
          const int vertex = vertex_base + static_cast<int>(v) + 1;  // 1-based, assimp's order
          const std::array<double, 3> xyz{p.x, p.y, p.z};
          static constexpr const char* kAxis[3] = {"x", "y", "z"};
          for (int axis = 0; axis < 3; ++axis)
            if (!std::isfinite(xyz[axis])) {
              std::ostringstream value;
              value << xyz[axis];
              throw IoError(file.string() + ": vertex " + std::to_string(vertex) + " (triangle " +
                            std::to_string(number) + ", corner " + std::to_string(c + 1) +
                            ") has a non-finite coordinate (" + kAxis[axis] + " = " + value.str() +
                            "); every coordinate must be a finite number");
            }
          const auto [it, added] = node_at.emplace(xyz, static_cast<int>(nodes.size()));
          if (added) {
            nodes.emplace_back(xyz[0], xyz[1], xyz[2]);
            origin->vertex_number.push_back(vertex);
            origin->vertex_line.push_back(0);
          }
          node_of[v] = it->second;
        }
        triangle[c] = node_of[v];
      }
      triangles.push_back(triangle);
    }
    // Unused vertices of a mesh of triangles (SortByPType put points and lines apart).
    if ((mesh.mPrimitiveTypes & (aiPrimitiveType_POINT | aiPrimitiveType_LINE)) == 0)
      for (unsigned v = 0; v < mesh.mNumVertices; ++v)
        if (node_of[v] < 0 && unused++ == 0)
          origin->first_unreferenced = vertex_base + static_cast<int>(v) + 1;
    vertex_base += static_cast<int>(mesh.mNumVertices);
  }
  origin->unreferenced_count = unused;
  if (triangles.empty())
    throw IoError(file.string() + ": the mesh file holds no triangles; a shell needs triangles" +
                  (skipped_primitives > 0 ? " (it has only points or lines)" : ""));
  if (skipped_primitives > 0)
    spdlog::warn("{}: {} points or lines left out (a shell is made of its triangles only)",
                 file.string(), skipped_primitives);

  SurfaceMesh out = to_mesh(nodes, triangles);
  out.origin = std::move(origin);
  return out;
}

}  // namespace

std::vector<std::string> mesh_file_extensions() {
  std::vector<std::string> out{".obj"};
  aiString list;  // "*.3ds;*.obj;*.dae;..."
  aiGetExtensionList(&list);
  std::istringstream in(list.C_Str());
  std::string pattern;
  while (std::getline(in, pattern, ';')) {
    if (pattern.rfind("*", 0) == 0) pattern.erase(0, 1);
    if (!pattern.empty() && pattern != ".obj") out.push_back(pattern);
  }
  return out;
}

SurfaceMesh load_mesh_file(const std::filesystem::path& file) {
  const std::string ext = lower_extension(file);
  if (ext == ".obj") return load_obj(file);  // which checks the file itself
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw IoError(file.string() +
                  ": cannot read the mesh file: no such file (check the path; "
                  "a relative path is taken from the scene file's folder)");
  if (ext.empty() || !aiIsExtensionSupported(ext.c_str()))
    throw IoError(file.string() + ": '" + ext +
                  "' is not a mesh format shellflow reads; use .obj, .stl, .ply, .gltf, "
                  ".glb, .fbx, .dae or another format assimp reads");
  return import_with_assimp(file);
}

}  // namespace shellflow::geometry
