#include "shellflow/grid_fluid/water/initial_water.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "shellflow/geometry/mesh_generators.hpp"
#include "shellflow/geometry/triangle_bvh.hpp"
#include "shellflow/grid_fluid/mac/domain_overlap.hpp"
#include "shellflow/grid_fluid/smoke/smoke_source.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::grid_fluid {

using grid::Location;

sdk::Schema initial_water_schema() {
  using sdk::Schema;
  // Every shape can also carve its inside out of the water before it (Zalesak's slot).
  const auto shape = [](Schema object) {
    return object.field("subtract", Schema::boolean(false).doc(
                                        "true: remove this shape's inside from the water of the "
                                        "entries before it (φ = max(φ, −d)) instead of adding it"));
  };
  return Schema::variant("type", "a body of water at the start")
      .option("pool", shape(Schema::object("water below a height along the up direction (-gravity)")
                                .field("height", Schema::number().unit("m").doc(
                                                     "level of the surface: x·up = height"))))
      .option("box", shape(Schema::object("an axis-aligned box of water")
                               .field("min", Schema::vec3().unit("m").doc("corner"))
                               .field("max", Schema::vec3().unit("m").doc("opposite corner"))))
      .option("sphere",
              shape(Schema::object("a ball of water")
                        .field("center", Schema::vec3().unit("m").doc("centre"))
                        .field("radius", Schema::number().min(0.0, false).unit("m").doc("radius"))))
      .option("cylinder",
              shape(Schema::object("a solid cylinder of water between two points (water "
                                   "standing in a cup: its radius that of the cup)")
                        .field("from", Schema::vec3().unit("m").doc("centre of one end"))
                        .field("to", Schema::vec3().unit("m").doc("centre of the other end"))
                        .field("radius", Schema::number().min(0.0, false).unit("m").doc("radius"))))
      .option("mesh", shape(Schema::object("the inside of a closed triangle mesh")
                                .field("mesh", geometry::mesh_schema())
                                .field("transform", geometry::transform_schema())));
}

namespace {

/// (b − a) × (q − a) in the y–z plane, computed from the edge's endpoints in one fixed
/// order whichever way the edge is passed: the two triangles that share an edge get
/// exactly opposite values, so the tie rule below gives a point on it to exactly one.
double edge_function(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& q) {
  const bool ordered = a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  const Eigen::Vector2d& lo = ordered ? a : b;
  const Eigen::Vector2d& hi = ordered ? b : a;
  const double e = (hi.x() - lo.x()) * (q.y() - lo.y()) - (hi.y() - lo.y()) * (q.x() - lo.x());
  return ordered ? e : -e;
}

/// Where the line {(t, y, z)} crosses the triangle, if it does. A line through an edge or
/// a vertex crosses exactly one of the triangles about it (the "top-left" rule of
/// rasterisers: an edge of value 0 counts only when it runs one way), and a line grazing
/// the mesh's outline crosses none or two, so the parity of the crossings is the inside
/// wherever the rows of nodes run through the mesh's edges (a rotated box's rows did).
std::optional<double> row_crossing(const geometry::TriangleCorners& c, double y, double z) {
  std::array<Eigen::Vector2d, 3> p;
  for (int v = 0; v < 3; ++v) p[v] = Eigen::Vector2d(c[v].y(), c[v].z());
  const Eigen::Vector2d q(y, z);
  double e[3];  // e[v]: the edge opposite vertex v, from v+1 to v+2
  for (int v = 0; v < 3; ++v) e[v] = edge_function(p[(v + 1) % 3], p[(v + 2) % 3], q);
  const double area = edge_function(p[0], p[1], p[2]);
  if (area == 0.0) return std::nullopt;  // seen edge-on: the line grazes it
  const double orientation = area > 0.0 ? 1.0 : -1.0;
  for (int v = 0; v < 3; ++v) {
    const double value = orientation * e[v];
    if (value < 0.0) return std::nullopt;
    if (value == 0.0) {
      // On the edge: owned only when it runs "up" (or "left" when level), in the
      // triangle's counter-clockwise order.
      Eigen::Vector2d d = p[(v + 2) % 3] - p[(v + 1) % 3];
      if (orientation < 0.0) d = -d;
      if (!(d.y() > 0.0 || (d.y() == 0.0 && d.x() < 0.0))) return std::nullopt;
    }
  }
  const double sum = e[0] + e[1] + e[2];
  return (e[0] * c[0].x() + e[1] * c[1].x() + e[2] * c[2].x()) / sum;
}

/// φ = min(φ, d), or max(φ, −d) with `subtract`, for d the signed distance of the closed
/// mesh, on the nodes of its box grown by band (beyond it d ≥ band changes nothing).
void fill_mesh(const geometry::SurfaceMesh& surface, bool subtract, LevelSet& level_set) {
  const grid::UniformGrid& grid = level_set.grid();
  const double band = level_set.band();
  const geometry::TriangleMesh mesh(surface.positions, surface.triangles);
  const geometry::TriangleBvh bvh(mesh);
  const Eigen::Vector3d lo = surface.positions.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = surface.positions.colwise().maxCoeff().transpose();
  const grid::IndexBox box =
      grid.samples_in_box(Location::Node, lo.array() - band, hi.array() + band);
  if (box.empty()) return;
  auto& phi = level_set.phi();
#pragma omp parallel
  {
    std::vector<double> crossings;
#pragma omp for collapse(2) schedule(dynamic, 4)
    for (int k = box.lo.z(); k <= box.hi.z(); ++k)
      for (int j = box.lo.y(); j <= box.hi.y(); ++j) {
        // Crossings of the row's line with the mesh, for the sign.
        const Eigen::Vector3d row = grid.position(Location::Node, Eigen::Vector3i(0, j, k));
        const double y = row.y(), z = row.z();
        const Eigen::Vector3d a(lo.x() - 1.0, y, z), b(hi.x() + 1.0, y, z);
        crossings.clear();
        bvh.triangles_near_segment(a, b, 0.0, [&](int t) {
          if (const auto x = row_crossing(mesh.corners(t), y, z)) crossings.push_back(*x);
          return false;
        });
        std::sort(crossings.begin(), crossings.end());
        for (int i = box.lo.x(); i <= box.hi.x(); ++i) {
          const Eigen::Vector3d p = grid.position(Location::Node, Eigen::Vector3i(i, j, k));
          const auto after = std::upper_bound(crossings.begin(), crossings.end(), p.x());
          const bool inside = (crossings.end() - after) % 2 == 1;
          const auto closest = bvh.closest_point(p, band);
          const double d = closest.triangle >= 0 ? std::sqrt(closest.distance2) : band;
          double& v = phi[grid.index(Location::Node, i, j, k)];
          v = subtract ? std::max(v, inside ? d : -d) : std::min(v, inside ? -d : d);
        }
      }
  }
}

}  // namespace

void fill_initial_water(const nlohmann::json& entries, const Eigen::Vector3d& up,
                        const std::string& json_path, LevelSet& level_set) {
  const grid::UniformGrid& grid = level_set.grid();
  const grid::UniformGrid& mac = level_set.mac_grid();  // the domain
  auto& phi = level_set.phi();
  const std::int64_t count = grid.size(Location::Node);
  for (size_t e = 0; e < entries.size(); ++e) {
    const auto& spec = entries[e];
    const std::string path = json_path + "/" + std::to_string(e);
    const std::string type = spec.at("type").get<std::string>();
    const bool subtract = spec.at("subtract").get<bool>();
    std::function<double(const Eigen::Vector3d&)> distance;
    // Whether the entry shares a volume with the domain (one that does not, or only touches
    // a face, fills no cell), and what it is and where, for the message if not.
    bool reaches = false;
    std::string shape;
    std::string fix = kMoveInsideDomain;
    std::optional<geometry::SurfaceMesh> surface;
    if (type == "pool") {
      const double height = spec.at("height").get<double>();
      distance = [=](const Eigen::Vector3d& p) { return p.dot(up) - height; };
      // Water where x·up < height: the domain's lowest x·up (at its corner furthest down)
      // must lie below the surface.
      const Eigen::AlignedBox3d domain = domain_box(mac);
      const Eigen::Vector3d lo = domain.min().cwiseProduct(up), hi = domain.max().cwiseProduct(up);
      const double lowest = lo.cwiseMin(hi).sum(), highest = lo.cwiseMax(hi).sum();
      reaches = lowest < height;
      const Eigen::Vector3d shown = up.array() + 0.0;  // + 0: no "-0" of a negated gravity
      shape = fmt::format(
          "the pool (water where x·up < {:g}; x·up spans [{:g}, {:g}] over the "
          "domain, up = ({:g}, {:g}, {:g}))",
          height, lowest + 0.0, highest + 0.0, shown.x(), shown.y(), shown.z());
      fix = fmt::format("raise its height above {:g} (the domain's lowest x·up), or remove it",
                        lowest);
    } else if (type == "box") {
      const Eigen::Vector3d lo = sdk::json_vec3(spec, "min"), hi = sdk::json_vec3(spec, "max");
      if ((hi.array() <= lo.array()).any())
        throw ConfigError(path + "/max", "every coordinate of max must exceed min's");
      distance = [=](const Eigen::Vector3d& p) {
        const Eigen::Vector3d q = (p - 0.5 * (lo + hi)).cwiseAbs() - 0.5 * (hi - lo);
        return std::min(q.maxCoeff(), 0.0) + q.cwiseMax(0.0).norm();
      };
      reaches = overlaps_domain(mac, Eigen::AlignedBox3d(lo, hi));
      shape = "the box " + box_text(Eigen::AlignedBox3d(lo, hi));
    } else if (type == "sphere") {
      const Eigen::Vector3d c = sdk::json_vec3(spec, "center");
      const double r = spec.at("radius").get<double>();
      distance = [=](const Eigen::Vector3d& p) { return (p - c).norm() - r; };
      reaches = overlaps_domain(mac, c, r);
      shape =
          "the sphere (bounds " + box_text(Eigen::AlignedBox3d(c.array() - r, c.array() + r)) + ")";
    } else if (type == "cylinder") {
      // The emitters' capped cylinder (its checks name this entry's keys).
      const SmokeSource cylinder({{"shape", "cylinder"},
                                  {"from", spec.at("from")},
                                  {"to", spec.at("to")},
                                  {"radius", spec.at("radius")}},
                                 path);
      distance = [cylinder](const Eigen::Vector3d& p) { return cylinder.signed_distance(p); };
      // By its bounding box, as the emitters' cylinders (SmokeSource::require_in_domain).
      reaches = overlaps_domain(mac, cylinder.bounds());
      shape = "the cylinder (bounds " + box_text(cylinder.bounds()) + ")";
    } else {
      surface = geometry::make_mesh(spec.at("mesh"), path + "/mesh");
      geometry::apply_transform(
          geometry::transform_from_json(spec.value("transform", nlohmann::json::object()),
                                        path + "/transform"),
          *surface);
      const Eigen::AlignedBox3d bounds(surface->positions.colwise().minCoeff().transpose(),
                                       surface->positions.colwise().maxCoeff().transpose());
      reaches = overlaps_domain(mac, bounds);
      shape = "the mesh, transformed (bounds " + box_text(bounds) + ")";
    }
    if (!reaches)
      throw outside_domain(mac, path, shape,
                           subtract ? "it would remove no water" : "it would add no water", fix);
    if (surface) {
      fill_mesh(*surface, subtract, level_set);
      continue;
    }
    if (subtract) {
#pragma omp parallel for schedule(static)
      for (std::int64_t i = 0; i < count; ++i)
        phi[i] = std::max(phi[i], -distance(grid.position(Location::Node, i)));
    } else {
#pragma omp parallel for schedule(static)
      for (std::int64_t i = 0; i < count; ++i)
        phi[i] = std::min(phi[i], distance(grid.position(Location::Node, i)));
    }
  }
  const double band = level_set.band();
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < count; ++i) phi[i] = std::clamp(phi[i], -band, band);
}

}  // namespace shellflow::grid_fluid
