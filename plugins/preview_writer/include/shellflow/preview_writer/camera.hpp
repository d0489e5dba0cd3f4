#pragma once
// Camera: a pinhole camera (position, look-at point, up vector, vertical field of view)
// that turns pixel (x, y) of a width x height image, row 0 at the top, into a ray
// through the pixel's centre.

#include <Eigen/Core>

namespace shellflow::preview_writer {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  ///< unit length
};

class Camera {
 public:
  /// @throw std::invalid_argument when look_at == position, up is parallel to the view
  /// direction, the field of view is outside (0°, 180°) or the size is not positive.
  Camera(const Eigen::Vector3d& position, const Eigen::Vector3d& look_at, const Eigen::Vector3d& up,
         double vertical_fov_deg, int width, int height);

  /// The ray through the centre of pixel (x, y).
  Ray pixel_ray(int x, int y) const;

  int width() const { return m_width; }
  int height() const { return m_height; }
  const Eigen::Vector3d& position() const { return m_position; }
  const Eigen::Vector3d& forward() const { return m_forward; }
  const Eigen::Vector3d& right() const { return m_right; }
  const Eigen::Vector3d& up() const { return m_up; }
  /// The side of a pixel on the image plane at unit distance along forward(): pixel_ray's
  /// unnormalised direction forward + sx right + sy up moves by pixel_size() right per
  /// pixel in x and by pixel_size() down per pixel in y (square pixels).
  double pixel_size() const { return 2.0 * m_tan_half_fov / m_height; }

 private:
  Eigen::Vector3d m_position;
  Eigen::Vector3d m_forward;  ///< unit view direction
  Eigen::Vector3d m_right;    ///< unit, image +x
  Eigen::Vector3d m_up;       ///< unit, image +y (up on screen)
  double m_tan_half_fov = 0.0;
  int m_width = 0;
  int m_height = 0;
};

}  // namespace shellflow::preview_writer
