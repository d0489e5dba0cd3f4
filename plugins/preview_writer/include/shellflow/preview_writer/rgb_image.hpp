#pragma once
// RgbImage: 8-bit RGB pixels, rows from the top, and its PNG output (stb_image_write).

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace shellflow::preview_writer {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 bytes per pixel, pixel (x, y) at 3 (x + width y)

  RgbImage() = default;
  RgbImage(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(3) * w * h, 0) {}

  /// Colour components in [0, 1] → bytes round(255 c) (clamped): error ≤ 0.5/255.
  void set(int x, int y, const Eigen::Vector3d& colour);
  Eigen::Vector3i at(int x, int y) const;
};

/// The byte for colour component c: round(255 clamp(c, 0, 1)).
std::uint8_t quantise(double c);

/// Writes `image` as a PNG through a temporary file renamed into place.
/// @throw IoError naming the file.
void write_png(const std::filesystem::path& file, const RgbImage& image);

}  // namespace shellflow::preview_writer
