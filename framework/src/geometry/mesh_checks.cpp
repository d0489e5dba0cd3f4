#include "shellflow/geometry/mesh_checks.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "shellflow/sdk/error.hpp"

namespace shellflow::geometry {

namespace {

/// Names mesh nodes as the user knows them: an OBJ's vertex number and line, or a node index.
class NodeNames {
 public:
  explicit NodeNames(const MeshOrigin* origin) : m_origin(origin) {}

  std::string operator()(int node) const {
    if (!m_origin) return "node " + std::to_string(node);
    if (node < 0 || node >= static_cast<int>(m_origin->vertex_number.size()))
      return "node " + std::to_string(node);
    return vertex(m_origin->vertex_number[static_cast<size_t>(node)],
                  m_origin->vertex_line[static_cast<size_t>(node)]);
  }
  static std::string vertex(int number, int line) {
    return "vertex " + std::to_string(number) +
           (line > 0 ? " (line " + std::to_string(line) + ")" : "");
  }
  /// "nodes 3, 4 and 5" or "vertices 3 (line 5), 4 (line 6) and 5 (line 7)".
  std::string list(std::initializer_list<int> nodes) const {
    std::string out = m_origin ? "vertices " : "nodes ";
    size_t k = 0;
    for (const int n : nodes) {
      std::string name = (*this)(n);
      name = name.substr(name.find(' ') + 1);  // without "vertex "/"node "
      if (k > 0) out += k + 1 == nodes.size() ? " and " : ", ";
      out += name;
      ++k;
    }
    return out;
  }

 private:
  const MeshOrigin* m_origin;
};

std::string format_point(const Eigen::Vector3d& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

std::string plural(int count, const std::string& one, const std::string& many) {
  return std::to_string(count) + " " + (count == 1 ? one : many);
}

}  // namespace

MeshCheckReport check_mesh(const SurfaceMesh& mesh, const MeshCheckPolicy& policy,
                           const std::string& json_path, const std::string& owner) {
  const MeshOrigin* origin = mesh.origin.get();
  const NodeNames name(origin);
  const std::string prefix = origin ? origin->file.string() + ": " : "";
  const std::string path = origin ? json_path + "/file" : json_path;
  const auto n = static_cast<int>(mesh.positions.rows());
  const auto& tris = mesh.triangles;

  // Errors whatever the policy: nothing below makes sense without them.
  if (tris.rows() == 0)
    throw ConfigError(path, prefix + "the mesh has no triangles; a shell needs at least one");
  for (int i = 0; i < n; ++i)
    if (!mesh.positions.row(i).allFinite())
      throw ConfigError(json_path, prefix + name(i) + " is at " +
                                       format_point(mesh.positions.row(i).transpose()) +
                                       ", not a finite position (a \"transform\" too large for "
                                       "double precision?)");
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int c = 0; c < 3; ++c)
      if (tris(t, c) < 0 || tris(t, c) >= n)
        throw ConfigError(path, prefix + "triangle " + std::to_string(t) + " refers to node " +
                                    std::to_string(tris(t, c)) + ", but the mesh has " +
                                    std::to_string(n) + " nodes");

  MeshCheckReport report;
  std::vector<std::string> errors;
  const auto found = [&](MeshCheckSeverity severity, const std::string& text) {
    if (severity == MeshCheckSeverity::Error)
      errors.push_back(text);
    else
      report.warnings.push_back(text);
  };

  // Zero-area triangles.
  std::vector<char> used(static_cast<size_t>(n), 0);
  Eigen::Index first_degenerate = -1;
  for (Eigen::Index t = 0; t < tris.rows(); ++t) {
    const int a = tris(t, 0), b = tris(t, 1), c = tris(t, 2);
    used[a] = used[b] = used[c] = 1;
    const Eigen::Vector3d xa = mesh.positions.row(a), xb = mesh.positions.row(b),
                          xc = mesh.positions.row(c);
    const double longest2 =
        std::max({(xb - xa).squaredNorm(), (xc - xb).squaredNorm(), (xa - xc).squaredNorm()});
    const double twice_area = (xb - xa).cross(xc - xa).norm();
    const bool degenerate =
        a == b || b == c || c == a || !(twice_area > kDegenerateRatio * longest2);
    if (degenerate && report.degenerate_triangles++ == 0) first_degenerate = t;
  }
  if (report.degenerate_triangles > 0) {
    const auto t = first_degenerate;
    found(policy.degenerate_triangles,
          plural(report.degenerate_triangles, "triangle has", "triangles have") +
              " zero area (the first: triangle " + std::to_string(t) + " with " +
              name.list({tris(t, 0), tris(t, 1), tris(t, 2)}) +
              "); merge coincident vertices or remove those triangles");
  }

  // Vertices no triangle uses: those load_obj dropped, and any a generator left.
  int first_unused = -1;
  for (int i = 0; i < n; ++i)
    if (!used[i] && report.unreferenced_vertices++ == 0) first_unused = i;
  std::string first_unused_name = first_unused >= 0 ? name(first_unused) : "";
  if (origin && origin->unreferenced_count > 0) {
    report.unreferenced_vertices += origin->unreferenced_count;
    first_unused_name =
        NodeNames::vertex(origin->first_unreferenced, origin->first_unreferenced_line);
  }
  if (report.unreferenced_vertices > 0)
    found(policy.unreferenced_vertices,
          plural(report.unreferenced_vertices, "vertex is", "vertices are") +
              " used by no triangle (the first: " + first_unused_name +
              "); they are dropped, which renumbers the vertices after them: delete loose "
              "vertices from the file");

  // Edges of more than two triangles: sort the (smaller, larger, triangle) records.
  std::vector<std::array<int, 3>> edges;
  edges.reserve(3 * static_cast<size_t>(tris.rows()));
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int p = tris(t, k), q = tris(t, (k + 1) % 3);
      if (p != q) edges.push_back({std::min(p, q), std::max(p, q), static_cast<int>(t)});
    }
  std::sort(edges.begin(), edges.end());
  std::array<int, 3> worst{};  // first offending edge: a, b, how many triangles
  for (size_t s = 0; s < edges.size();) {
    size_t e = s;
    while (e < edges.size() && edges[e][0] == edges[s][0] && edges[e][1] == edges[s][1]) ++e;
    if (e - s > 2 && report.non_manifold_edges++ == 0)
      worst = {edges[s][0], edges[s][1], static_cast<int>(e - s)};
    s = e;
  }
  if (report.non_manifold_edges > 0)
    found(policy.non_manifold_edges,
          plural(report.non_manifold_edges, "edge is", "edges are") +
              " shared by more than two triangles (the first: the edge between " +
              name.list({worst[0], worst[1]}) + ", in " + std::to_string(worst[2]) +
              " triangles); each edge may border at most two triangles: split the mesh "
              "there or remove the extra triangles");

  for (auto& w : report.warnings) w += " (a warning: this solid copes with them)";
  for (const auto& w : report.warnings)
    spdlog::warn("{}{}{}: {}", owner, owner.empty() ? "" : ": ", json_path, prefix + w);
  if (!errors.empty()) {
    std::string text = prefix + errors.front();
    for (size_t k = 1; k < errors.size(); ++k) text += "; also " + errors[k];
    throw ConfigError(path, text);
  }
  return report;
}

}  // namespace shellflow::geometry
