#include "shellflow/preview_writer/rgb_image.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include "shellflow/sdk/atomic_file.hpp"
#include "shellflow/sdk/error.hpp"

// stb_image_write (public domain, libstb-dev), compiled here with internal linkage so
// that another plugin embedding it cannot clash.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace shellflow::preview_writer {

std::uint8_t quantise(double c) {
  if (!(c > 0.0)) return 0;  // also NaN
  return static_cast<std::uint8_t>(std::lround(255.0 * std::min(c, 1.0)));
}

void RgbImage::set(int x, int y, const Eigen::Vector3d& colour) {
  std::uint8_t* p = rgb.data() + 3 * (static_cast<size_t>(x) + static_cast<size_t>(width) * y);
  for (int c = 0; c < 3; ++c) p[c] = quantise(colour[c]);
}

Eigen::Vector3i RgbImage::at(int x, int y) const {
  const std::uint8_t* p =
      rgb.data() + 3 * (static_cast<size_t>(x) + static_cast<size_t>(width) * y);
  return {p[0], p[1], p[2]};
}

namespace {

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

void write_png(const std::filesystem::path& file, const RgbImage& image) {
  std::vector<std::uint8_t> encoded;
  if (image.width <= 0 || image.height <= 0 ||
      !stbi_write_png_to_func(&append_bytes, &encoded, image.width, image.height, 3,
                              image.rgb.data(), 3 * image.width))
    throw IoError(file.string() + ": cannot encode the PNG image");

  sdk::write_file_atomically(file, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(encoded.data()),
              static_cast<std::streamsize>(encoded.size()));
  });
}

}  // namespace shellflow::preview_writer
