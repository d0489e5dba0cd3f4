#include "shellflow/preview_writer/rgb_image.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

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

  // Complete files or none: a hidden per-process temporary in the same folder (rename(2)
  // is atomic only within one file system), renamed into place.
  std::string temporary_name = ".";
  temporary_name.append(file.filename().string()).append(".tmp").append(std::to_string(::getpid()));
  const auto temporary = file.parent_path() / temporary_name;
  auto fail = [&](const std::string& what) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw IoError(file.string() + ": " + what);
  };
  std::FILE* out = std::fopen(temporary.c_str(), "wb");
  if (!out) fail(std::string("cannot create the file (") + std::strerror(errno) + ")");
  const size_t written = std::fwrite(encoded.data(), 1, encoded.size(), out);
  const bool closed = std::fclose(out) == 0;
  if (written != encoded.size() || !closed) fail("write failed (disk full?)");
  std::error_code ec;
  std::filesystem::rename(temporary, file, ec);
  if (ec) fail("cannot move the finished file into place (" + ec.message() + ")");
}

}  // namespace shellflow::preview_writer
