#include "shellflow/preview_writer/preview_renderer.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "shellflow/preview_writer/shell_scene.hpp"
#include "shellflow/preview_writer/smoke_volume.hpp"
#include "shellflow/sdk/error.hpp"
#include "shellflow/sdk/fluid_solver.hpp"

namespace shellflow::preview_writer {

namespace {

// The march stops once σ∫ρ ds exceeds this: T < e^-20 ≈ 2e-9, far below one 8-bit level.
constexpr double kOpaqueOpticalDepth = 20.0;

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

PreviewRenderer::PreviewRenderer(const PreviewSettings& settings)
    : m_settings(settings),
      m_camera(settings.camera_position, settings.look_at, settings.up, settings.vertical_fov_deg,
               settings.width, settings.height) {}

RgbImage PreviewRenderer::render(const sdk::FrameView& frame) const {
  const ShellScene shells(frame.shells);
  std::optional<SmokeVolume> smoke;
  std::vector<sdk::FieldView> fields;  // keeps the views alive for the render
  if (frame.fluid != nullptr) {
    fields = frame.fluid->fields();
    if (auto density = find_field(fields, m_settings.density_field)) {
      try {
        smoke.emplace(*density);
      } catch (const std::invalid_argument& e) {
        throw Error(std::string("preview_writer: ") + e.what());
      }
    }
  }
  const double sigma = m_settings.absorption;
  const double step = smoke ? m_settings.step_voxels * smoke->dx() : 0.0;
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
      Eigen::Vector3d behind = s.background_color;
      double smoke_end = std::numeric_limits<double>::infinity();
      if (!shells.empty()) {
        const ShellHit hit = shells.first_hit(ray.origin, ray.direction, hit_range);
        if (hit.hit()) {
          // Lambert with a headlight (light along the view ray), two-sided.
          const double lambert = std::abs(hit.normal.dot(ray.direction));
          behind = s.shell_color * (s.ambient + (1.0 - s.ambient) * lambert);
          smoke_end = hit.distance;  // smoke behind the shell stays hidden
        }
      }
      double transmittance = 1.0;
      if (smoke && sigma > 0.0) {
        const double depth =
            smoke->optical_depth(ray.origin, ray.direction, 0.0, smoke_end, step, max_depth);
        transmittance = std::exp(-sigma * depth);  // Beer–Lambert
      }
      image.set(x, y, s.smoke_color * (1.0 - transmittance) + transmittance * behind);
    }
  }
  return image;
}

}  // namespace shellflow::preview_writer
