#include "shellflow/grid_fluid/smoke/smoke_source.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "shellflow/grid_fluid/mac/domain_overlap.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::grid_fluid {

namespace {
sdk::Schema with_common_fields(sdk::Schema s, bool smoke) {
  using sdk::Schema;
  s.field("velocity", Schema::vec3().optional().unit("m/s").doc(
                          "velocity held on the faces of the emitter's cells in every "
                          "pressure solve; with an open domain side the emitter adds "
                          "that volume (fed from outside), in a closed box it draws it "
                          "from around itself (left out: no velocity)"));
  if (smoke)
    s.field("density", Schema::number(1.0).min(0.0).unit("1").doc("smoke density set inside"))
        .field("temperature", Schema::number().optional().min(0.0).unit("K").doc(
                                  "temperature set inside (any source with one turns the "
                                  "temperature field and its buoyancy on)"));
  return s.field("start", Schema::number(0.0).unit("s").doc("time the emitter turns on"))
      .field("end", Schema::number().optional().unit("s").doc(
                        "time the emitter turns off (left out: never)"));
}
}  // namespace

sdk::Schema SmokeSource::schema(bool smoke) {
  using sdk::Schema;
  return Schema::variant("shape", smoke ? "a smoke emitter" : "a water emitter")
      .option("sphere",
              with_common_fields(
                  Schema::object("a ball")
                      .field("center", Schema::vec3().unit("m").doc("centre"))
                      .field("radius", Schema::number().min(0.0, false).unit("m").doc("radius")),
                  smoke))
      .option("box",
              with_common_fields(Schema::object("an axis-aligned box")
                                     .field("min", Schema::vec3().unit("m").doc("corner"))
                                     .field("max", Schema::vec3().unit("m").doc("opposite corner")),
                                 smoke))
      .option("cylinder",
              with_common_fields(
                  Schema::object("a solid cylinder between two points (a nozzle; PhysBAM's "
                                 "smoke jets)")
                      .field("from", Schema::vec3().unit("m").doc("centre of one end"))
                      .field("to", Schema::vec3().unit("m").doc("centre of the other end"))
                      .field("radius", Schema::number().min(0.0, false).unit("m").doc("radius")),
                  smoke));
}

SmokeSource::SmokeSource(const nlohmann::json& spec, const std::string& json_path) {
  const std::string shape = spec.value("shape", std::string("sphere"));
  if (shape == "sphere") {
    m_shape = Shape::Sphere;
    m_center = sdk::json_vec3(spec, "center");
    m_radius = spec.at("radius").get<double>();
  } else if (shape == "box") {
    m_shape = Shape::Box;
    m_min = sdk::json_vec3(spec, "min");
    m_max = sdk::json_vec3(spec, "max");
    if ((m_max.array() <= m_min.array()).any())
      throw ConfigError(json_path + "/max", "every coordinate of max must exceed min's");
  } else if (shape == "cylinder") {
    m_shape = Shape::Cylinder;
    m_min = sdk::json_vec3(spec, "from");
    m_max = sdk::json_vec3(spec, "to");
    m_radius = spec.at("radius").get<double>();
    if ((m_max - m_min).norm() == 0.0)
      throw ConfigError(json_path + "/to", "must differ from \"from\" (the cylinder's axis)");
  } else {
    throw ConfigError(json_path + "/shape",
                      "unknown shape \"" + shape + "\"; use sphere, box or cylinder");
  }
  if (spec.contains("velocity") && !spec.at("velocity").is_null())
    m_velocity = sdk::json_vec3(spec, "velocity");
  m_density = spec.value("density", 1.0);
  if (spec.contains("temperature") && !spec.at("temperature").is_null())
    m_temperature = spec.at("temperature").get<double>();
  m_start = spec.value("start", 0.0);
  m_end = spec.contains("end") && !spec.at("end").is_null()
              ? spec.at("end").get<double>()
              : std::numeric_limits<double>::infinity();
  if (!(m_end > m_start)) throw ConfigError(json_path + "/end", "must be later than \"start\"");
}

bool SmokeSource::contains(const Eigen::Vector3d& p) const {
  if (m_shape == Shape::Sphere) return (p - m_center).squaredNorm() <= m_radius * m_radius;
  if (m_shape == Shape::Cylinder) {  // m_min, m_max: the ends of the axis
    const Eigen::Vector3d axis = m_max - m_min;
    const double s = (p - m_min).dot(axis) / axis.squaredNorm();
    return s >= 0.0 && s <= 1.0 && (p - m_min - s * axis).squaredNorm() <= m_radius * m_radius;
  }
  return (p.array() >= m_min.array()).all() && (p.array() <= m_max.array()).all();
}

double SmokeSource::signed_distance(const Eigen::Vector3d& p) const {
  if (m_shape == Shape::Sphere) return (p - m_center).norm() - m_radius;
  if (m_shape == Shape::Cylinder) {  // a capped cylinder: radial and axial distances
    const Eigen::Vector3d axis = m_max - m_min;
    const double length = axis.norm();
    const double along = (p - m_min).dot(axis) / length;
    const double radial = (p - m_min - along / length * axis).norm();
    const Eigen::Vector2d d(radial - m_radius, std::abs(along - 0.5 * length) - 0.5 * length);
    return std::min(d.maxCoeff(), 0.0) + d.cwiseMax(0.0).norm();
  }
  const Eigen::Vector3d half = 0.5 * (m_max - m_min);
  const Eigen::Vector3d q = (p - 0.5 * (m_min + m_max)).cwiseAbs() - half;
  return std::min(q.maxCoeff(), 0.0) + q.cwiseMax(0.0).norm();
}

Eigen::AlignedBox3d SmokeSource::bounds() const {
  if (m_shape == Shape::Sphere)
    return Eigen::AlignedBox3d(m_center.array() - m_radius, m_center.array() + m_radius);
  if (m_shape == Shape::Cylinder)
    return Eigen::AlignedBox3d(m_min.cwiseMin(m_max).array() - m_radius,
                               m_min.cwiseMax(m_max).array() + m_radius);
  return Eigen::AlignedBox3d(m_min, m_max);
}

void SmokeSource::require_in_domain(const grid::UniformGrid& grid, const std::string& json_path,
                                    const std::string& consequence) const {
  const bool overlaps = m_shape == Shape::Sphere ? overlaps_domain(grid, m_center, m_radius)
                                                 : overlaps_domain(grid, bounds());
  if (overlaps) return;
  static const char* kNames[] = {"sphere", "box", "cylinder"};
  throw outside_domain(grid, json_path,
                       fmt::format("the {} emitter (bounds {})", kNames[static_cast<int>(m_shape)],
                                   box_text(bounds())),
                       consequence, kMoveInsideDomain);
}

grid::IndexBox SmokeSource::bounding_samples(const grid::UniformGrid& grid, grid::Location loc,
                                             double margin) const {
  const Eigen::AlignedBox3d box = bounds();
  return grid.samples_in_box(loc, box.min().array() - margin, box.max().array() + margin);
}

void SmokeSource::append_faces(double t, const grid::UniformGrid& grid, int axis,
                               bool closed_intake, std::vector<SourceFace>& out) const {
  if (!active(t) || !m_velocity) return;
  const grid::IndexBox cells = bounding_samples(grid, grid::Location::Cell);
  if (cells.empty()) return;
  const auto loc = static_cast<grid::Location>(static_cast<int>(grid::Location::FaceX) + axis);
  const auto inside = [&](Eigen::Vector3i c) {  // an emitter cell: its centre lies inside
    if ((c.array() < 0).any() || (c.array() >= grid.cells().array()).any()) return false;
    return contains(grid.position(grid::Location::Cell, c));
  };
  const double along = (*m_velocity)[axis];
  Eigen::Vector3d intake_velocity = *m_velocity;
  if (closed_intake) intake_velocity[axis] = 0.0;
  Eigen::Vector3i hi = cells.hi;
  hi[axis] += 1;  // the faces on both sides of every emitter cell
  for (int k = cells.lo.z(); k <= hi.z(); ++k)
    for (int j = cells.lo.y(); j <= hi.y(); ++j)
      for (int i = cells.lo.x(); i <= hi.x(); ++i) {
        const Eigen::Vector3i face(i, j, k);  // the cell on its + side has its coordinates
        Eigen::Vector3i minus = face;
        minus[axis] -= 1;
        const bool in_minus = inside(minus);
        const bool in_plus = inside(face);
        if (!in_minus && !in_plus) continue;
        // On the emitter's surface, flow into the emitter is intake.
        const bool intake = in_minus != in_plus && (in_minus ? along < 0.0 : along > 0.0);
        out.push_back({grid.index(loc, face), intake ? intake_velocity : *m_velocity});
      }
}

std::int64_t SmokeSource::apply(double t, const grid::UniformGrid& grid, NodeFields& fields,
                                bool temperature) const {
  if (!active(t)) return 0;
  const grid::IndexBox box = bounding_samples(grid, grid::Location::Node);
  if (box.empty()) return 0;
  std::int64_t set = 0;
#pragma omp parallel for collapse(2) reduction(+ : set)
  for (int k = box.lo.z(); k <= box.hi.z(); ++k)
    for (int j = box.lo.y(); j <= box.hi.y(); ++j)
      for (int i = box.lo.x(); i <= box.hi.x(); ++i) {
        const Eigen::Vector3i ijk(i, j, k);
        if (!contains(grid.position(grid::Location::Node, ijk))) continue;
        const std::int64_t node = grid.index(grid::Location::Node, ijk);
        fields.density()[node] = m_density;
        if (temperature && m_temperature) fields.temperature()[node] = *m_temperature;
        ++set;
      }
  return set;
}

}  // namespace shellflow::grid_fluid
