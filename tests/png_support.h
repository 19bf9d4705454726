#pragma once
// The browser tests' helpers: finding headless Chromium and reading its screenshots (link
// PNG::PNG).

#include <cstdlib>
#include <filesystem>
#include <string>
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

/// The Chromium executable on PATH, or empty.
inline std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    const std::string cmd = std::string("command -v ") + name + " >/dev/null 2>&1";
    if (std::system(cmd.c_str()) == 0) return name;
  }
  return "";
}

}  // namespace gridshell::test
