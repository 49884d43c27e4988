// PNG reading and writing for tests, through the frame driver's codec (drivers/frames/png).
#include "tests/support/png_image.hpp"

#include "drivers/frames/png.hpp"

namespace ccdlane::test {

PngImage read_png(const std::string& path) {
  OwnedPicture picture = read_png_picture(path);
  PngImage out;
  out.width = picture.width;
  out.height = picture.height;
  out.format = picture.format;
  out.pixels = std::move(picture.pixels);
  return out;
}

void write_png(const std::string& path, const ImageView& image) {
  if (image.format != PixelFormat::mono8 && image.format != PixelFormat::rgb8)
    throw std::runtime_error(path + ": only mono8 and rgb8 images are written");
  ccdlane::write_png(path, image, 6);
}

}  // namespace ccdlane::test
