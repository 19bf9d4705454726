#pragma once
// Reading headless Chromium's screenshots in the browser tests (link PNG::PNG).

#include <filesystem>
#include <vector>

#include <png.h>

namespace gridshell::test {

struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  ///< 3 bytes per pixel, rows top to bottom
  const unsigned char* at(int x, int y) const { return &rgb[3 * (y * width + x)]; }
};

/// The PNG at `path` as RGB; an empty image when it cannot be read.
inline Image read_png(const std::filesystem::path& path) {
  Image im;
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) return im;
  png.format = PNG_FORMAT_RGB;
  im.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, im.rgb.data(), 0, nullptr)) return {};
  im.width = static_cast<int>(png.width);
  im.height = static_cast<int>(png.height);
  return im;
}

}  // namespace gridshell::test
