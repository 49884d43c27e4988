// PNG reading and writing for tests (libpng's simplified API).
#include "tests/support/png_image.hpp"

#include <png.h>

#include <cstring>
#include <stdexcept>

namespace ccdlane::test {

PngImage read_png(const std::string& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    throw std::runtime_error(path + ": cannot read PNG: " + png.message);
  const bool colour = (png.format & PNG_FORMAT_FLAG_COLOR) != 0;
  png.format = colour ? PNG_FORMAT_RGB : PNG_FORMAT_GRAY;
  PngImage out;
  out.width = static_cast<int>(png.width);
  out.height = static_cast<int>(png.height);
  out.format = colour ? PixelFormat::rgb8 : PixelFormat::mono8;
  out.pixels.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, out.pixels.data(), 0, nullptr)) {
    png_image_free(&png);
    throw std::runtime_error(path + ": cannot decode PNG: " + png.message);
  }
  return out;
}

void write_png(const std::string& path, const ImageView& image) {
  if (image.format != PixelFormat::mono8 && image.format != PixelFormat::rgb8)
    throw std::runtime_error(path + ": only mono8 and rgb8 images are written");
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = image.format == PixelFormat::rgb8 ? PNG_FORMAT_RGB : PNG_FORMAT_GRAY;
  if (!png_image_write_to_file(&png, path.c_str(), 0, image.data, static_cast<png_int_32>(image.stride_bytes), nullptr))
    throw std::runtime_error(path + ": cannot write PNG: " + png.message);
}

}  // namespace ccdlane::test
