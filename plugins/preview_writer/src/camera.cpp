#include "shellflow/preview_writer/camera.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace shellflow::preview_writer {

Camera::Camera(const Eigen::Vector3d& position, const Eigen::Vector3d& look_at,
               const Eigen::Vector3d& up, double vertical_fov_deg, int width, int height)
    : m_position(position), m_width(width), m_height(height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("image size must be positive");
  if (!(vertical_fov_deg > 0.0 && vertical_fov_deg < 180.0))
    throw std::invalid_argument("the vertical field of view must lie in (0, 180) degrees");
  const Eigen::Vector3d view = look_at - position;
  if (!(view.norm() > 0.0)) throw std::invalid_argument("look_at equals the camera position");
  m_forward = view.normalized();
  const Eigen::Vector3d right = m_forward.cross(up);
  // |f x u| = sin(angle) |u|: below 1e-9 the up vector gives no usable roll.
  if (!(right.norm() > 1e-9 * up.norm()) || !(up.norm() > 0.0))
    throw std::invalid_argument("up is zero or parallel to the view direction");
  m_right = right.normalized();
  m_up = m_right.cross(m_forward);
  m_tan_half_fov = std::tan(0.5 * vertical_fov_deg * std::numbers::pi / 180.0);
}

Ray Camera::pixel_ray(int x, int y) const {
  const double aspect = static_cast<double>(m_width) / m_height;
  const double sx = (2.0 * (x + 0.5) / m_width - 1.0) * m_tan_half_fov * aspect;
  const double sy = (1.0 - 2.0 * (y + 0.5) / m_height) * m_tan_half_fov;
  return {m_position, (m_forward + sx * m_right + sy * m_up).normalized()};
}

}  // namespace shellflow::preview_writer
