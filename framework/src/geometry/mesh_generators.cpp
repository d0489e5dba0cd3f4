#include "shellflow/geometry/mesh_generators.hpp"

#include <spdlog/spdlog.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "shellflow/geometry/mesh_import.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::geometry {

namespace {

using Json = nlohmann::json;
using SchemaJson = sdk::Schema::Json;

void require(bool condition, const char* function, const std::string& what) {
  if (!condition) throw std::invalid_argument(std::string(function) + ": " + what);
}

/// Splits quad (a, b, c, d), counter-clockwise seen from its front, into two triangles
/// along a–c (`along_ac`) or along b–d; both keep the quad's orientation.
void add_quad(std::vector<std::array<int, 3>>& triangles, int a, int b, int c, int d,
              bool along_ac) {
  if (along_ac) {
    triangles.push_back({a, b, c});
    triangles.push_back({a, c, d});
  } else {
    triangles.push_back({a, b, d});
    triangles.push_back({b, c, d});
  }
}

/// Box surface on the (n+1)^3 lattice of a box centred at the origin; faces listed by
/// (axis, side). Nodes are numbered on first use so that shared edges share nodes
/// (watertight) and an omitted face leaves no orphan nodes.
SurfaceMesh make_box_faces(const Eigen::Vector3d& size, int n, bool with_top) {
  const int m = n + 1;
  std::vector<int> index(static_cast<size_t>(m) * m * m, -1);
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 3>> triangles;
  auto node = [&](const std::array<int, 3>& ijk) {
    int& id = index[static_cast<size_t>(ijk[0] + m * (ijk[1] + m * ijk[2]))];
    if (id < 0) {
      id = static_cast<int>(nodes.size());
      Eigen::Vector3d p;
      for (int a = 0; a < 3; ++a) p[a] = size[a] * (static_cast<double>(ijk[a]) / n - 0.5);
      nodes.push_back(p);
    }
    return id;
  };
  for (int axis = 0; axis < 3; ++axis) {
    // (u, v, axis) is a cyclic permutation of (x, y, z): e_u × e_v = e_axis.
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      if (!with_top && axis == 1 && side == 1) continue;  // the cup is open towards +y
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          auto corner = [&](int di, int dj) {
            std::array<int, 3> ijk{};
            ijk[axis] = side * n;
            ijk[u] = i + di;
            ijk[v] = j + dj;
            return node(ijk);
          };
          const int a = corner(0, 0), b = corner(1, 0), c = corner(1, 1), d = corner(0, 1);
          // Alternate the diagonals like a checkerboard: no preferred shear direction.
          const bool along_ac = (i + j) % 2 == 0;
          if (side == 1)
            add_quad(triangles, a, b, c, d, along_ac);  // normal +e_axis
          else
            add_quad(triangles, a, d, c, b, along_ac);  // normal −e_axis
        }
    }
  }
  return to_mesh(nodes, triangles);
}

template <class T>
T field(const Json& spec, const SchemaJson& fields, const std::string& name) {
  if (spec.contains(name)) return spec.at(name).get<T>();
  return fields.at(name).at("default").get<T>();
}

Eigen::Vector3d vec3_field(const Json& spec, const SchemaJson& fields, const std::string& name,
                           const std::string& json_path) {
  const auto values = field<std::vector<double>>(spec, fields, name);
  if (values.size() != 3)
    throw ConfigError(json_path + "/" + name, "expected three numbers [x, y, z]");
  return {values[0], values[1], values[2]};
}

}  // namespace

SurfaceMesh to_mesh(const std::vector<Eigen::Vector3d>& nodes,
                    const std::vector<std::array<int, 3>>& triangles) {
  SurfaceMesh mesh;
  mesh.positions.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (size_t i = 0; i < nodes.size(); ++i)
    mesh.positions.row(static_cast<Eigen::Index>(i)) = nodes[i].transpose();
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) mesh.triangles(static_cast<Eigen::Index>(t), c) = triangles[t][c];
  return mesh;
}

SurfaceMesh make_grid(double width, double height, int nodes_u, int nodes_v, GridPattern pattern) {
  require(width > 0 && height > 0, "make_grid", "width and height must be positive");
  require(nodes_u >= 2 && nodes_v >= 2, "make_grid", "need at least 2 nodes along each side");
  std::vector<Eigen::Vector3d> nodes;
  nodes.reserve(static_cast<size_t>(nodes_u) * nodes_v);
  for (int j = 0; j < nodes_v; ++j)
    for (int i = 0; i < nodes_u; ++i)
      nodes.emplace_back(width * (static_cast<double>(i) / (nodes_u - 1) - 0.5),
                         height * (static_cast<double>(j) / (nodes_v - 1) - 0.5), 0.0);
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(2 * static_cast<size_t>(nodes_u - 1) * (nodes_v - 1));
  auto id = [nodes_u](int i, int j) { return i + nodes_u * j; };
  for (int j = 0; j + 1 < nodes_v; ++j)
    for (int i = 0; i + 1 < nodes_u; ++i) {
      bool along_ac = true;  // diagonal from (i, j) to (i+1, j+1)
      switch (pattern) {
        case GridPattern::Regular:
          along_ac = true;
          break;
        case GridPattern::Herringbone:
          along_ac = i % 2 == 0;
          break;
        case GridPattern::Alternating:
          along_ac = (i + j) % 2 == 0;
          break;
      }
      // Counter-clockwise seen from +z: the grid's normal is +z.
      add_quad(triangles, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1), along_ac);
    }
  return to_mesh(nodes, triangles);
}

SurfaceMesh make_box(const Eigen::Vector3d& size, int divisions) {
  require((size.array() > 0).all(), "make_box", "every side length must be positive");
  require(divisions >= 1, "make_box", "divisions must be at least 1");
  return make_box_faces(size, divisions, true);
}

SurfaceMesh make_open_box(const Eigen::Vector3d& size, int divisions) {
  require((size.array() > 0).all(), "make_open_box", "every side length must be positive");
  require(divisions >= 1, "make_open_box", "divisions must be at least 1");
  return make_box_faces(size, divisions, false);
}

SurfaceMesh make_open_cylinder(double radius, double height, int segments, int rings,
                               bool bottom_cap) {
  require(radius > 0 && height > 0, "make_open_cylinder", "radius and height must be positive");
  require(segments >= 3, "make_open_cylinder", "segments must be at least 3");
  require(rings >= 1, "make_open_cylinder", "rings must be at least 1");
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 3>> triangles;
  // Node (s, r) at angle θ_s = 2π s / segments on ring r (height r/rings · height), placed
  // at (R cos θ, y, −R sin θ) so that quads (s, r), (s+1, r), (s+1, r+1), (s, r+1) face
  // outwards: ∂x/∂θ × ∂x/∂y = (cos θ, 0, −sin θ) R.
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = 2.0 * std::numbers::pi * s / segments;
      nodes.emplace_back(radius * std::cos(theta), height * r / rings, -radius * std::sin(theta));
    }
  auto id = [segments](int s, int r) { return (s % segments) + segments * r; };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s)
      add_quad(triangles, id(s, r), id(s + 1, r), id(s + 1, r + 1), id(s, r + 1), (s + r) % 2 == 0);
  if (bottom_cap) {
    // A fan around a centre node; (centre, s+1, s) faces −y.
    const int centre = static_cast<int>(nodes.size());
    nodes.emplace_back(0.0, 0.0, 0.0);
    for (int s = 0; s < segments; ++s) triangles.push_back({centre, id(s + 1, 0), id(s, 0)});
  }
  return to_mesh(nodes, triangles);
}

namespace {

/// Triangles between two rows of `count` nodes each (first_a + k, first_b + k), or a pole
/// (one node) for a row whose first is given with `a_pole`/`b_pole`; closed round (`ring`)
/// or open (the row's ends are separate). Quads (k, a), (k+1, a), (k+1, b), (k, b) keep
/// add_quad's orientation; a pole turns them into triangles.
void add_band(std::vector<std::array<int, 3>>& triangles, int first_a, bool a_pole, int first_b,
              bool b_pole, int count, bool ring, int parity) {
  const int cells = ring ? count : count - 1;
  for (int k = 0; k < cells; ++k) {
    const int next = (k + 1) % count;
    const int a0 = a_pole ? first_a : first_a + k, a1 = a_pole ? first_a : first_a + next;
    const int b0 = b_pole ? first_b : first_b + k, b1 = b_pole ? first_b : first_b + next;
    if (a_pole)
      triangles.push_back({a0, b1, b0});
    else if (b_pole)
      triangles.push_back({a0, a1, b0});
    else
      add_quad(triangles, a0, a1, b1, b0, (k + parity) % 2 == 0);
  }
}

}  // namespace

SurfaceMesh make_revolution(const std::vector<Eigen::Vector2d>& profile, int segments, int rings) {
  require(profile.size() >= 2, "make_revolution", "the profile needs at least two points");
  require(segments >= 3, "make_revolution", "segments must be at least 3");
  double length = 0.0, scale = 0.0;
  for (size_t i = 0; i < profile.size(); ++i) {
    require(profile[i].allFinite() && profile[i].x() >= 0.0, "make_revolution",
            "profile point " + std::to_string(i) + " must be finite with r >= 0");
    scale = std::max(scale, profile[i].cwiseAbs().maxCoeff());
    if (i > 0) length += (profile[i] - profile[i - 1]).norm();
  }
  const double on_axis = 1e-12 * scale;
  for (size_t i = 1; i < profile.size(); ++i) {
    require((profile[i] - profile[i - 1]).norm() > on_axis, "make_revolution",
            "profile points " + std::to_string(i - 1) + " and " + std::to_string(i) +
                " coincide");
    require(profile[i].x() > on_axis || profile[i - 1].x() > on_axis, "make_revolution",
            "profile segment " + std::to_string(i - 1) + " lies on the axis (it sweeps no area)");
  }
  require(rings >= static_cast<int>(profile.size()) - 1, "make_revolution",
          "rings must be at least the profile's segment count (" +
              std::to_string(profile.size() - 1) + ")");
  // Equal arc length cells, the profile's corners kept: each segment gets its share of
  // `rings` (at least one), the remainders going to the largest fractions.
  std::vector<int> cells(profile.size() - 1);
  std::vector<std::pair<double, size_t>> remainder;
  int used = 0;
  for (size_t i = 0; i + 1 < profile.size(); ++i) {
    const double share = rings * (profile[i + 1] - profile[i]).norm() / length;
    cells[i] = std::max(1, static_cast<int>(std::floor(share)));
    used += cells[i];
    remainder.emplace_back(share - std::floor(share), i);
  }
  std::sort(remainder.begin(), remainder.end(), std::greater<>());
  for (size_t k = 0; used < rings; k = (k + 1) % remainder.size(), ++used) ++cells[remainder[k].second];
  std::vector<Eigen::Vector2d> points;
  for (size_t i = 0; i + 1 < profile.size(); ++i)
    for (int c = 0; c < cells[i]; ++c)
      points.push_back(profile[i] + (profile[i + 1] - profile[i]) * (double(c) / cells[i]));
  points.push_back(profile.back());

  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> first(points.size());
  std::vector<bool> pole(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    first[i] = static_cast<int>(nodes.size());
    pole[i] = points[i].x() <= on_axis;
    if (pole[i]) {
      nodes.emplace_back(0.0, points[i].y(), 0.0);
      continue;
    }
    // As make_open_cylinder: (r cos θ, y, −r sin θ) faces outwards for a profile going up.
    for (int k = 0; k < segments; ++k) {
      const double theta = 2.0 * std::numbers::pi * k / segments;
      nodes.emplace_back(points[i].x() * std::cos(theta), points[i].y(),
                         -points[i].x() * std::sin(theta));
    }
  }
  for (size_t i = 0; i + 1 < points.size(); ++i)
    add_band(triangles, first[i], pole[i], first[i + 1], pole[i + 1], segments, true,
             static_cast<int>(i));
  return to_mesh(nodes, triangles);
}

SurfaceMesh make_boat_hull(double length, double beam, double depth, double fullness,
                           int stations, int sections) {
  require(length > 0 && beam > 0 && depth > 0, "make_boat_hull",
          "length, beam and depth must be positive");
  require(fullness >= 1.0 && std::isfinite(fullness), "make_boat_hull",
          "fullness must be at least 1 (2: round sections)");
  require(stations >= 2, "make_boat_hull", "stations must be at least 2");
  require(sections >= 2, "make_boat_hull", "sections must be at least 2");
  // A superellipse's coordinate: sign(t) |t|^(2/n).
  const auto shape = [fullness](double t) {
    return std::copysign(std::pow(std::abs(t), 2.0 / fullness), t);
  };
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> first(stations + 1);
  // Station u = −1 (stern, −x) to +1 (bow); node (i, j) at angle φ_j from −π/2 (the −z
  // gunwale) through 0 (the keel) to π/2: ∂/∂u × ∂/∂φ faces outwards.
  for (int i = 0; i <= stations; ++i) {
    first[i] = static_cast<int>(nodes.size());
    const double u = -1.0 + 2.0 * i / stations;
    const double x = 0.5 * length * u;
    if (i == 0 || i == stations) {
      nodes.emplace_back(x, 0.0, 0.0);  // bow and stern: the sections close to a point
      continue;
    }
    const double half_beam = 0.5 * beam * std::sqrt(1.0 - u * u);
    const double keel = depth * std::sqrt(1.0 - u * u * u * u);
    for (int j = 0; j <= sections; ++j) {
      const double phi = std::numbers::pi * (double(j) / sections - 0.5);
      const bool gunwale = j == 0 || j == sections;  // exactly in y = 0 (cos(±π/2) is not)
      nodes.emplace_back(x, gunwale ? 0.0 : -keel * shape(std::cos(phi)),
                         gunwale ? (j == 0 ? -half_beam : half_beam) : half_beam * shape(std::sin(phi)));
    }
  }
  // Rows in the order (i + 1, i): add_band's quads then face ∂/∂φ × −∂/∂u, outwards.
  for (int i = 0; i < stations; ++i)
    add_band(triangles, first[i + 1], i + 1 == stations, first[i], i == 0, sections + 1, false, i);
  return to_mesh(nodes, triangles);
}

SurfaceMesh make_sphere(double radius, int subdivisions) {
  require(radius > 0, "make_sphere", "radius must be positive");
  require(subdivisions >= 0 && subdivisions <= 9, "make_sphere",
          "subdivisions must lie in [0, 9] (20·4^9 triangles already)");
  // Icosahedron (counter-clockwise seen from outside), each subdivision splitting every
  // triangle into four at its edge midpoints, new nodes projected onto the sphere.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> nodes = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                        {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                        {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : nodes) p = radius * p.normalized();
  std::vector<std::array<int, 3>> triangles = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      const int id = static_cast<int>(nodes.size());
      nodes.push_back(radius * (nodes[a] + nodes[b]).normalized());
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(4 * triangles.size());
    for (const auto& [a, b, c] : triangles) {
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    triangles = std::move(finer);
  }
  return to_mesh(nodes, triangles);
}

namespace {

/// The line of each "v" statement of an OBJ file, after checking that its three
/// coordinates are finite numbers. tinyobjloader parses numbers itself and reads "nan" as
/// 0 without a word, and keeps no line numbers: hence this scan. @throw IoError naming the
/// file, the line and the vertex (1-based, as faces count them).
std::vector<int> scan_obj_vertices(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<int> lines;
  std::string text;
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  for (int line = 1; std::getline(in, text); ++line) {
    size_t i = text.find_first_not_of(" \t");
    if (i == std::string::npos || text[i] != 'v' || i + 1 >= text.size() ||
        (text[i + 1] != ' ' && text[i + 1] != '\t'))
      continue;  // not a "v" statement ("vt", "vn", comments and faces are tinyobj's)
    lines.push_back(line);
    const int vertex = static_cast<int>(lines.size());
    std::istringstream fields(text.substr(i + 1));
    const std::string where =
        file.string() + ":" + std::to_string(line) + ": vertex " + std::to_string(vertex);
    for (int axis = 0; axis < 3; ++axis) {
      std::string token;
      if (!(fields >> token))
        throw IoError(where + " has " + std::to_string(axis) +
                      " coordinates; a vertex needs three (\"v x y z\")");
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0')
        throw IoError(where + ": its " + kAxis[axis] + " coordinate '" + token +
                      "' is not a number");
      if (!std::isfinite(value))
        throw IoError(where + " has a non-finite coordinate (" + kAxis[axis] + " = " + token +
                      "); every coordinate must be a finite number");
    }
  }
  return lines;
}

}  // namespace

SurfaceMesh load_obj(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw IoError(file.string() +
                  ": cannot read the OBJ file: no such file (check the path; "
                  "a relative path is taken from the scene file's folder)");
  const std::vector<int> vertex_lines = scan_obj_vertices(file);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warning, error;
  const std::string base = file.parent_path().string() + "/";
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error,
                                   file.string().c_str(), base.c_str(), /*triangulate=*/true);
  if (!ok) throw IoError(file.string() + ": cannot read the OBJ file: " + error);
  if (!warning.empty()) spdlog::warn("{}: {}", file.string(), warning);

  // Only vertices that some face uses become mesh nodes (an orphan node would carry no
  // area and no mass); they keep the file's order. How many were dropped is kept for
  // check_mesh(), which reports them as each solid decides.
  const size_t vertex_count = attrib.vertices.size() / 3;
  std::vector<std::array<int, 3>> triangles;
  std::vector<char> used(vertex_count, 0);
  for (const auto& shape : shapes) {
    size_t offset = 0;
    for (const auto corners : shape.mesh.num_face_vertices) {
      if (corners != 3)
        throw IoError(file.string() + ": face with " + std::to_string(corners) +
                      " corners left after triangulation");
      std::array<int, 3> triangle{};
      for (int c = 0; c < 3; ++c) {
        const int v = shape.mesh.indices[offset + c].vertex_index;
        if (v < 0 || static_cast<size_t>(v) >= vertex_count)
          throw IoError(file.string() + ": face refers to vertex " + std::to_string(v + 1) +
                        ", but the file has " + std::to_string(vertex_count) + " vertices");
        triangle[c] = v;
        used[v] = 1;
      }
      triangles.push_back(triangle);
      offset += 3;
    }
  }
  if (triangles.empty())
    throw IoError(file.string() + ": the OBJ file holds no faces; a shell needs triangles");
  // Line numbers only when both readers agree on the vertices (a construct the scan does
  // not know, such as a line continuation, leaves them out rather than wrong).
  const bool have_lines = vertex_lines.size() == vertex_count;
  auto origin = std::make_shared<MeshOrigin>();
  origin->file = file;
  std::vector<int> renumber(vertex_count, -1);
  std::vector<Eigen::Vector3d> nodes;
  for (size_t v = 0; v < vertex_count; ++v) {
    const int line = have_lines ? vertex_lines[v] : 0;
    if (!used[v]) {
      if (origin->unreferenced_count++ == 0) {
        origin->first_unreferenced = static_cast<int>(v) + 1;
        origin->first_unreferenced_line = line;
      }
      continue;
    }
    renumber[v] = static_cast<int>(nodes.size());
    nodes.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1],
                       attrib.vertices[3 * v + 2]);
    origin->vertex_number.push_back(static_cast<int>(v) + 1);
    origin->vertex_line.push_back(line);
  }
  for (auto& triangle : triangles)
    for (int& v : triangle) v = renumber[v];
  SurfaceMesh mesh = to_mesh(nodes, triangles);
  mesh.origin = std::move(origin);
  return mesh;
}

sdk::Schema mesh_schema() {
  using sdk::Schema;
  // Counts along one side are capped so that a typo cannot ask for billions of nodes: 4096²
  // nodes (16.8 M) is far beyond what a shell in this simulator is run with. Lengths are
  // positive numbers; box sizes (vec3, which the schema cannot bound) are checked in
  // make_mesh; sphere subdivisions and box divisions have their own caps.
  constexpr double kMaxNodesPerSide = 4096;
  auto length = [](double value, const std::string& doc) {
    return Schema::number(value).min(0.0, false).unit("m").doc(doc);
  };
  return Schema::variant("type", "shape of the shell, before \"transform\"")
      .option("grid",
              Schema::object("rectangle in the x–y plane (normal +z) centred at the origin; node "
                             "(i, j) has index i + nodes_u·j")
                  .field("width", length(1.0, "side along x"))
                  .field("height", length(1.0, "side along y"))
                  .field("nodes_u",
                         Schema::integer(11).min(2).max(kMaxNodesPerSide).doc("nodes along x"))
                  .field("nodes_v",
                         Schema::integer(11).min(2).max(kMaxNodesPerSide).doc("nodes along y"))
                  .field("pattern", Schema::string("regular")
                                        .one_of({"regular", "herringbone", "alternating"})
                                        .doc("quad diagonals: all alike, alternating per column "
                                             "(PhysBAM cloth), or checkerboard")))
      .option("box", Schema::object("closed box centred at the origin, outward normals")
                         .field("size", Schema::vec3(1.0, 1.0, 1.0)
                                            .unit("m")
                                            .doc("side lengths along x, y, z (positive)"))
                         .field("divisions", Schema::integer(4).min(1).max(256).doc(
                                                 "cells per edge on every face")))
      .option("open_box", Schema::object("box without its +y face (a cup), centred at the origin")
                              .field("size", Schema::vec3(1.0, 1.0, 1.0)
                                                 .unit("m")
                                                 .doc("side lengths along x, y, z (positive)"))
                              .field("divisions", Schema::integer(4).min(1).max(256).doc(
                                                      "cells per edge on every face")))
      .option(
          "open_cylinder",
          Schema::object("cylinder side about +y from y = 0 to y = height, open at the "
                         "top (a cup)")
              .field("radius", length(0.5, "radius"))
              .field("height", length(1.0, "height"))
              .field("segments",
                     Schema::integer(32).min(3).max(kMaxNodesPerSide).doc("nodes around the axis"))
              .field("rings",
                     Schema::integer(8).min(1).max(kMaxNodesPerSide).doc("cells along the axis"))
              .field("bottom_cap",
                     Schema::boolean(true).doc("close the bottom with a triangle fan")))
      .option("revolution",
              Schema::object("surface of revolution about +y of a profile of [r, y] points "
                             "(a goblet, a vase, a cup with a floor); a point with r = 0 is "
                             "one node on the axis")
                  .field("profile",
                         Schema::array(Schema::number_list()).doc(
                             "[[r, y], ...] from one end to the other, r >= 0 [m]; normals "
                             "face right of the direction of travel (outwards going up)"))
                  .field("segments",
                         Schema::integer(64).min(3).max(kMaxNodesPerSide).doc("nodes around the axis"))
                  .field("rings", Schema::integer(32).min(1).max(kMaxNodesPerSide).doc(
                                      "cells along the profile, spread by arc length (at "
                                      "least one per profile segment)")))
      .option("boat_hull",
              Schema::object("open canoe-like hull along x, its gunwale in the plane y = 0, "
                             "keel below, pointed bow (+x) and stern; outward normals")
                  .field("length", length(1.0, "from stern to bow"))
                  .field("beam", length(0.3, "widest breadth, at mid-length"))
                  .field("depth", length(0.15, "keel below the gunwale, at mid-length"))
                  .field("fullness",
                         Schema::number(3.0).min(1.0).doc(
                             "section superellipse exponent: 2 round, larger a flatter "
                             "bottom and fuller sides"))
                  .field("stations",
                         Schema::integer(48).min(2).max(kMaxNodesPerSide).doc("cells along the length"))
                  .field("sections", Schema::integer(24).min(2).max(kMaxNodesPerSide).doc(
                                         "cells round each section, gunwale to gunwale")))
      .option("sphere",
              Schema::object("icosphere centred at the origin, outward normals")
                  .field("radius", length(0.5, "radius"))
                  .field("subdivisions", Schema::integer(3).min(0).max(7).doc(
                                             "icosahedron refinements: 20·4^n triangles")))
      .option("obj", Schema::object("triangle mesh read from a Wavefront OBJ file (polygons "
                                    "are triangulated; unused vertices dropped)")
                         .field("file", Schema::file().doc("path of the .obj file, relative "
                                                           "to the scene file")))
      .option("file",
              Schema::object("triangle mesh read from a file, its format by its extension: "
                             ".obj, .stl, .ply, .gltf, .glb, .fbx, .dae and the other formats "
                             "assimp reads (every mesh of the file, placed by its node "
                             "transforms; polygons triangulated; corners at the same position "
                             "joined; points and lines left out)")
                  .field("file", Schema::file().doc("path of the mesh file, relative to the "
                                                    "scene file")));
}

SurfaceMesh make_mesh(const nlohmann::json& spec, const std::string& json_path) {
  if (!spec.is_object() || !spec.contains("type") || !spec.at("type").is_string())
    throw ConfigError(json_path + "/type",
                      "a mesh needs a \"type\": grid, box, open_box, "
                      "open_cylinder, revolution, boat_hull, sphere, obj or file");
  const auto type = spec.at("type").get<std::string>();
  static const SchemaJson options = mesh_schema().json().at("options");
  if (!options.contains(type))
    throw ConfigError(json_path + "/type", "unknown mesh type \"" + type +
                                               "\"; use grid, box, open_box, open_cylinder, "
                                               "revolution, boat_hull, sphere, obj or file");
  // Defaults come from the one place they are declared: the schema.
  const auto& fields = options.at(type).at("fields");
  auto positive_size = [&]() {
    const Eigen::Vector3d size = vec3_field(spec, fields, "size", json_path);
    if (!(size.array() > 0).all())
      throw ConfigError(json_path + "/size", "every side length must be positive");
    return size;
  };
  if (type == "grid") {
    const auto pattern_name = field<std::string>(spec, fields, "pattern");
    GridPattern pattern = GridPattern::Regular;
    if (pattern_name == "herringbone")
      pattern = GridPattern::Herringbone;
    else if (pattern_name == "alternating")
      pattern = GridPattern::Alternating;
    else if (pattern_name != "regular")
      throw ConfigError(json_path + "/pattern",
                        "unknown pattern; use regular, herringbone or alternating");
    return make_grid(field<double>(spec, fields, "width"), field<double>(spec, fields, "height"),
                     field<int>(spec, fields, "nodes_u"), field<int>(spec, fields, "nodes_v"),
                     pattern);
  }
  if (type == "box") return make_box(positive_size(), field<int>(spec, fields, "divisions"));
  if (type == "open_box")
    return make_open_box(positive_size(), field<int>(spec, fields, "divisions"));
  if (type == "open_cylinder")
    return make_open_cylinder(
        field<double>(spec, fields, "radius"), field<double>(spec, fields, "height"),
        field<int>(spec, fields, "segments"), field<int>(spec, fields, "rings"),
        field<bool>(spec, fields, "bottom_cap"));
  if (type == "revolution") {
    const auto& points = spec.contains("profile") ? spec.at("profile") : Json();
    if (!points.is_array() || points.size() < 2)
      throw ConfigError(json_path + "/profile",
                        "a revolution needs \"profile\": at least two [r, y] points");
    std::vector<Eigen::Vector2d> profile;
    for (size_t i = 0; i < points.size(); ++i) {
      const std::string at = json_path + "/profile/" + std::to_string(i);
      if (!points[i].is_array() || points[i].size() != 2 || !points[i][0].is_number() ||
          !points[i][1].is_number())
        throw ConfigError(at, "expected [r, y], two numbers");
      profile.emplace_back(points[i][0].get<double>(), points[i][1].get<double>());
      if (!(profile.back().x() >= 0.0))
        throw ConfigError(at, "r is the distance from the axis: it must be >= 0");
      if (i > 0 && profile[i] == profile[i - 1])
        throw ConfigError(at, "this point repeats the one before it; remove one");
    }
    try {
      return make_revolution(profile, field<int>(spec, fields, "segments"),
                             field<int>(spec, fields, "rings"));
    } catch (const std::invalid_argument& e) {
      throw ConfigError(json_path, e.what());
    }
  }
  if (type == "boat_hull")
    return make_boat_hull(field<double>(spec, fields, "length"), field<double>(spec, fields, "beam"),
                          field<double>(spec, fields, "depth"), field<double>(spec, fields, "fullness"),
                          field<int>(spec, fields, "stations"), field<int>(spec, fields, "sections"));
  if (type == "sphere")
    return make_sphere(field<double>(spec, fields, "radius"),
                       field<int>(spec, fields, "subdivisions"));
  if (!spec.contains("file") || !spec.at("file").is_string())
    throw ConfigError(json_path + "/file", "a \"" + type + "\" mesh needs \"file\": the path of " +
                                               (type == "obj" ? "an .obj" : "a mesh file"));
  const std::filesystem::path file = spec.at("file").get<std::string>();
  try {
    return type == "obj" ? load_obj(file) : load_mesh_file(file);
  } catch (const IoError& e) {
    throw ConfigError(json_path + "/file", e.what());
  }
}

sdk::Schema transform_schema() {
  using sdk::Schema;
  return Schema::object(
             "placement: scale, then rotation about an axis through the origin, "
             "then translation")
      .field("scale", Schema::number(1.0).min(0.0, false).doc("uniform scale factor"))
      .field("rotate_axis", Schema::vec3(0.0, 1.0, 0.0).doc("rotation axis (any length but zero)"))
      .field("rotate_deg", Schema::number(0.0).unit("deg").doc("rotation angle, right-handed"))
      .field("translate", Schema::vec3(0.0, 0.0, 0.0).unit("m").doc("translation"));
}

Eigen::Affine3d transform_from_json(const nlohmann::json& spec, const std::string& json_path) {
  static const SchemaJson fields = transform_schema().json().at("fields");
  const Json empty = Json::object();
  const Json& s = spec.is_null() ? empty : spec;
  const auto scale = field<double>(s, fields, "scale");
  if (!(scale > 0)) throw ConfigError(json_path + "/scale", "scale must be positive");
  const Eigen::Vector3d axis = vec3_field(s, fields, "rotate_axis", json_path);
  const auto degrees = field<double>(s, fields, "rotate_deg");
  const Eigen::Vector3d translate = vec3_field(s, fields, "translate", json_path);
  if (degrees != 0.0 && !(axis.norm() > 0))
    throw ConfigError(json_path + "/rotate_axis", "the rotation axis must not be zero");
  Eigen::Affine3d transform = Eigen::Affine3d::Identity();
  transform.translate(translate);
  if (degrees != 0.0)
    transform.rotate(Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()));
  transform.scale(scale);
  return transform;
}

void apply_transform(const Eigen::Affine3d& transform, SurfaceMesh& mesh) {
  for (Eigen::Index i = 0; i < mesh.positions.rows(); ++i)
    mesh.positions.row(i) = (transform * Eigen::Vector3d(mesh.positions.row(i))).transpose();
}

}  // namespace shellflow::geometry
