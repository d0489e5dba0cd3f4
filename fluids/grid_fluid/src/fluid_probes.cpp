#include "shellflow/grid_fluid/fluid_probes.hpp"

#include "shellflow/grid_fluid/water/volume_fraction.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cmath>

#include "shellflow/grid_fluid/mac/domain_overlap.hpp"
#include "shellflow/grid_fluid/water/level_set.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/json_helpers.hpp"

namespace shellflow::grid_fluid {

using grid::Location;
using sdk::Schema;

namespace {
/// What a probe outside the domain should do: it reads the domain's faces too.
constexpr const char* kMoveProbe =
    "move it (or the domain) so that it meets the domain (its faces count), or remove it";

std::string point_text(const Eigen::Vector3d& p) {
  return fmt::format("({:g}, {:g}, {:g})", p.x(), p.y(), p.z());
}
}  // namespace

Schema FluidProbes::schema() {
  return Schema::array(
             Schema::variant("type", "a probe whose figures metrics.csv gets each step")
                 .option("box", Schema::object("smoke mass or water volume inside a box (water: "
                                               "the water fraction's in the cells whose centres "
                                               "lie in it; the level set's without one)")
                                    .field("name", Schema::string().doc(
                                                       "column prefix: <fluid>.<name>.smoke_mass "
                                                       "or .water_volume"))
                                    .field("min", Schema::vec3().unit("m").doc("lower corner"))
                                    .field("max", Schema::vec3().unit("m").doc("upper corner")))
                 .option("water_extent",
                         Schema::object("how far water reaches along a segment")
                             .field("name", Schema::string().doc("column prefix: "
                                                                 "<fluid>.<name>.extent [m]"))
                             .field("from", Schema::vec3().unit("m").doc("start of the segment"))
                             .field("to", Schema::vec3().unit("m").doc("end of the segment")))
                 .option("velocity_error",
                         Schema::object("the face velocities against an analytic field")
                             .field("name", Schema::string().doc(
                                                "column prefix: <fluid>.<name>.max_error and "
                                                ".rms_error (relative to the field's size)"))
                             .field("reference", AnalyticVelocity::schema())))
      .default_value(nlohmann::json::array())
      .doc("figures of regions and lines written to metrics.csv (for known answers)");
}

FluidProbes::FluidProbes(const nlohmann::json& probes, const std::string& path,
                         const grid::UniformGrid& grid) {
  for (size_t i = 0; i < probes.size(); ++i) {
    const auto& p = probes[i];
    Probe probe;
    probe.name = p.at("name").get<std::string>();
    const std::string here = path + "/" + std::to_string(i);
    if (probe.name.empty() || probe.name.find_first_of("., ") != std::string::npos)
      throw ConfigError(here + "/name",
                        "a probe name is a column prefix: non-empty, without "
                        "'.', ',' or spaces");
    for (const auto& other : m_probes)
      if (other.name == probe.name)
        throw ConfigError(here + "/name", "the probe name '" + probe.name + "' is used twice");
    if (p.at("type") == "box") {
      probe.type = Type::Box;
      probe.a = sdk::json_vec3(p, "min");
      probe.b = sdk::json_vec3(p, "max");
      if ((probe.b.array() < probe.a.array()).any())
        throw ConfigError(here + "/max", "each coordinate of max must be >= min's");
      // Closed: a flat box on a face of the domain still reads the nodes on it.
      const Eigen::AlignedBox3d box(probe.a, probe.b);
      if (!domain_box(grid).intersects(box))
        throw outside_domain(grid, here, "the box probe " + box_text(box), "it would always read 0",
                             kMoveProbe);
    } else if (p.at("type") == "velocity_error") {
      probe.type = Type::VelocityError;
      // Sampled once: the reference does not change, the report is then a plain sum.
      MacGrid sampled(grid);
      const AnalyticVelocity reference(p.at("reference"), grid, here + "/reference");
      if (!reference.steady())
        throw ConfigError(here + "/reference",
                          "the reference must not change with time (it is sampled once): "
                          "use taylor_green or rigid_rotation");
      reference.fill(sampled);
      double largest = 0.0;
      for (int a = 0; a < 3; ++a) {
        probe.reference[a] = sampled.face_velocity(a);
        for (const double w : probe.reference[a]) largest = std::max(largest, std::abs(w));
      }
      if (largest == 0.0)
        throw ConfigError(here + "/reference",
                          "the reference field is zero everywhere: an error relative to it "
                          "has no scale (give an amplitude)");
    } else {
      probe.type = Type::WaterExtent;
      probe.a = sdk::json_vec3(p, "from");
      probe.b = sdk::json_vec3(p, "to");
      if ((probe.b - probe.a).norm() == 0.0)
        throw ConfigError(here + "/to", "the segment has no length: give 'to' apart from 'from'");
      // Closed, as for boxes: a segment along a face of the domain (a floor) reads its nodes.
      if (!meets_domain(grid, probe.a, probe.b))
        throw outside_domain(grid, here,
                             "the water_extent probe's segment from " + point_text(probe.a) +
                                 " to " + point_text(probe.b),
                             "it would never sample the water in it", kMoveProbe);
    }
    m_probes.push_back(probe);
  }
}

void FluidProbes::report(sdk::Metrics& out, const MacGrid& mac, const std::vector<double>& density,
                         const LevelSet* level_set, const VolumeFraction* fraction) const {
  const grid::UniformGrid& grid = mac.grid();
  const double dx = grid.dx();
  const double cell = dx * dx * dx;
  for (const auto& p : m_probes) {
    if (p.type == Type::Box) {
      if (level_set) {
        // The water of the cells whose centres lie in the box: F's (water_volume's measure),
        // else the level set's sharp volume, as LevelSet::volume.
        const grid::IndexBox cells = grid.samples_in_box(Location::Cell, p.a, p.b);
        out.set(p.name + ".water_volume", fraction != nullptr && fraction->enabled()
                                              ? fraction->volume_in(cells)
                                              : level_set->volume(cells));
        continue;
      }
      const grid::IndexBox box = grid.samples_in_box(Location::Node, p.a, p.b);
      double sum = 0.0;
      if (!box.empty() && !density.empty())
        for (int k = box.lo.z(); k <= box.hi.z(); ++k)
          for (int j = box.lo.y(); j <= box.hi.y(); ++j)
            for (int i = box.lo.x(); i <= box.hi.x(); ++i)
              sum += density[grid.index(Location::Node, i, j, k)];
      out.set(p.name + ".smoke_mass", sum * cell);
    } else if (p.type == Type::VelocityError) {
      double max_error = 0.0, max_reference = 0.0, error_squares = 0.0, reference_squares = 0.0;
      for (int a = 0; a < 3; ++a) {
        const auto& u = mac.face_velocity(a);
        const auto& w = p.reference[a];
        for (size_t f = 0; f < u.size(); ++f) {
          const double e = u[f] - w[f];
          max_error = std::max(max_error, std::abs(e));
          max_reference = std::max(max_reference, std::abs(w[f]));
          error_squares += e * e;
          reference_squares += w[f] * w[f];
        }
      }
      out.set(p.name + ".max_error", max_error / max_reference);
      out.set(p.name + ".rms_error", std::sqrt(error_squares / reference_squares));
    } else {
      double extent = 0.0;
      if (level_set) {
        const double length = (p.b - p.a).norm();
        const int samples = std::max(2, static_cast<int>(std::ceil(4.0 * length / dx)) + 1);
        double previous = 0.0;
        for (int s = samples - 1; s >= 0; --s) {
          const double t = static_cast<double>(s) / (samples - 1);
          const double phi = level_set->sample(p.a + t * (p.b - p.a));
          if (phi <= 0.0) {
            extent = t * length;
            if (s < samples - 1)  // the crossing between this sample and the next one out
              extent += (length / (samples - 1)) * phi / (phi - previous);
            break;
          }
          previous = phi;
        }
      }
      out.set(p.name + ".extent", extent);
    }
  }
}

}  // namespace shellflow::grid_fluid
