#include "shellflow/preview_writer/preview_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "shellflow/preview_writer/shell_scene.hpp"
#include "shellflow/preview_writer/smoke_volume.hpp"
#include "shellflow/preview_writer/water_surface.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

namespace {

// The march stops once σ∫ρ ds exceeds this: T < e^-20 ≈ 2e-9, far below one 8-bit level.
constexpr double kOpaqueOpticalDepth = 20.0;
// Normal-incidence reflectance of water, ((n − 1)/(n + 1))² with n = 1.33.
constexpr double kWaterF0 = 0.02;
// The level set march never steps more than half a voxel (WaterSurface).
constexpr double kMaxWaterStepVoxels = 0.5;

std::optional<sdk::FieldView> find_field(const std::vector<sdk::FieldView>& fields,
                                         const std::string& name) {
  for (const auto& f : fields)
    if (f.name == name) return f;
  return std::nullopt;
}

/// Farthest distance from `p` to a point of the box (+ a margin), bounding every hit.
double far_distance(const geometry::Aabb& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = (box.lower - p).cwiseAbs().cwiseMax((box.upper - p).cwiseAbs());
  return d.norm() * (1.0 + 1e-9) + 1e-9;
}

}  // namespace

double water_fresnel(double cos_theta) {
  const double c = std::clamp(1.0 - cos_theta, 0.0, 1.0);
  const double c2 = c * c;
  return kWaterF0 + (1.0 - kWaterF0) * c2 * c2 * c;  // Schlick 1994
}

Eigen::Vector3d water_shade(const PreviewSettings& s, const Eigen::Vector3d& normal,
                            const Eigen::Vector3d& direction) {
  const double cos_theta = std::abs(normal.dot(direction));  // headlight, two-sided
  const double fresnel = water_fresnel(cos_theta);
  const Eigen::Vector3d lambert = s.water_color * (s.ambient + (1.0 - s.ambient) * cos_theta);
  return (1.0 - fresnel) * lambert + fresnel * s.water_rim_color;
}

PreviewRenderer::PreviewRenderer(const PreviewSettings& settings)
    : m_settings(settings),
      m_camera(settings.camera_position, settings.look_at, settings.up, settings.vertical_fov_deg,
               settings.width, settings.height) {}

std::shared_ptr<const DomainWalls> PreviewRenderer::walls(const sdk::DomainView& domain) const {
  const std::lock_guard<std::mutex> lock(m_walls_mutex);
  if (!m_walls || !(m_walls->domain() == domain))
    m_walls = std::make_shared<const DomainWalls>(domain, m_settings.down, m_settings.wall_colours,
                                                  m_camera);
  return m_walls;
}

RgbImage PreviewRenderer::render(const sdk::FrameView& frame) const {
  const ShellScene shells(frame.shells);
  std::shared_ptr<const DomainWalls> walls;
  if (m_settings.walls && frame.fluid != nullptr)
    if (const std::optional<sdk::DomainView> domain = frame.fluid->domain()) try {
        walls = this->walls(*domain);
      } catch (const std::invalid_argument& e) {
        throw Error(std::string("preview_writer: ") + e.what());
      }
  std::optional<SmokeVolume> smoke;
  std::optional<WaterSurface> water;
  std::vector<sdk::FieldView> fields;  // keeps the views alive for the render
  if (frame.fluid != nullptr) {
    fields = frame.fluid->fields();
    try {
      if (auto density = find_field(fields, m_settings.density_field)) smoke.emplace(*density);
      if (auto phi = find_field(fields, m_settings.water_field)) {
        water.emplace(*phi);
        if (!shells.empty()) water->see_shells(shells);
      }
    } catch (const std::invalid_argument& e) {
      throw Error(std::string("preview_writer: ") + e.what());
    }
  }
  std::optional<FloorShadow> shadow;
  if (walls && walls->floor() >= 0 && m_settings.floor_shadow > 0.0 && (water || smoke)) {
    shadow.emplace(walls->floor());
    if (auto phi = find_field(fields, m_settings.water_field)) shadow->add_water(*phi);
    if (auto density = find_field(fields, m_settings.density_field))
      shadow->add_smoke(*density, m_settings.absorption);
  }
  const double sigma = m_settings.absorption;
  const double step = smoke ? m_settings.step_voxels * smoke->dx() : 0.0;
  const double water_step =
      water ? std::min(m_settings.step_voxels, kMaxWaterStepVoxels) * water->dx() : 0.0;
  const double max_depth =
      sigma > 0.0 ? kOpaqueOpticalDepth / sigma : std::numeric_limits<double>::infinity();
  const double hit_range =
      shells.empty() ? 0.0 : far_distance(shells.bounds(), m_camera.position());
  const PreviewSettings& s = m_settings;

  RgbImage image(m_camera.width(), m_camera.height());
#pragma omp parallel for schedule(dynamic, 4)
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const Ray ray = m_camera.pixel_ray(x, y);
      const WallPixel* wall = walls ? &walls->pixel(x, y) : nullptr;
      Eigen::Vector3d behind = s.background_color;
      double smoke_end = std::numeric_limits<double>::infinity();
      if (wall != nullptr && wall->wall()) {
        behind = wall->colour;  // behind everything in the box
        smoke_end = wall->distance;
        if (shadow && wall->floor)
          behind *= 1.0 - s.floor_shadow * shadow->at(ray.origin + wall->distance * ray.direction);
      }
      double nearest = std::numeric_limits<double>::infinity();  // water or shell: hides edges
      double water_end = std::numeric_limits<double>::infinity();
      if (!shells.empty()) {
        const ShellHit hit = shells.first_hit(ray.origin, ray.direction, hit_range);
        if (hit.hit() && hit.distance < smoke_end) {
          // Lambert with a headlight (light along the view ray), two-sided.
          const double lambert = std::abs(hit.normal.dot(ray.direction));
          behind = s.shell_color * (s.ambient + (1.0 - s.ambient) * lambert);
          smoke_end = hit.distance;  // smoke and water behind the shell stay hidden
          nearest = hit.distance;
          // Water is looked for up to the shell less the simulation's wedge half-width
          // (1e-3 dx, GRID_BASED_COLLISION_GEOMETRY_UNIFORM): from a point on the shell
          // itself, which side's nodes it sees is round-off.
          if (water) water_end = hit.distance - 1e-3 * water->dx();
        }
      }
      if (water) {
        const WaterHit hit = water->first_hit(ray.origin, ray.direction, water_end, water_step);
        if (hit.hit()) {
          behind = water_shade(s, hit.normal, ray.direction);  // in front of any shell
          smoke_end = hit.distance;
          nearest = hit.distance;
        }
      }
      double transmittance = 1.0;
      if (smoke && sigma > 0.0) {
        const double depth =
            smoke->optical_depth(ray.origin, ray.direction, 0.0, smoke_end, step, max_depth);
        transmittance = std::exp(-sigma * depth);  // Beer–Lambert
      }
      Eigen::Vector3d colour = s.smoke_color * (1.0 - transmittance) + transmittance * behind;
      if (wall != nullptr && wall->edge_alpha > 0.0 && wall->edge_distance < nearest) {
        double edge_transmittance = 1.0;
        if (smoke && sigma > 0.0)
          edge_transmittance =
              std::exp(-sigma * smoke->optical_depth(ray.origin, ray.direction, 0.0,
                                                     wall->edge_distance, step, max_depth));
        const Eigen::Vector3d edge =
            s.smoke_color * (1.0 - edge_transmittance) + edge_transmittance * s.wall_colours.grid;
        colour = (1.0 - wall->edge_alpha) * colour + wall->edge_alpha * edge;
      }
      image.set(x, y, colour);
    }
  }
  return image;
}

}  // namespace shellflow::preview_writer
