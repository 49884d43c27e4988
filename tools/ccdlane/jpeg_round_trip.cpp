// libjpeg's part holds nothing with a destructor: its errors are a longjmp
// (jpeg_error_jump.hpp), and what they may leave to free is kept in memory (Coder), not in
// locals the jump could lose.
#include "tools/ccdlane/jpeg_round_trip.hpp"

#include <cstdlib>
#include <stdexcept>

#include "drivers/frames/jpeg_error_jump.hpp"

namespace ccdlane::cli {
namespace {

struct Coder {
  JpegErrorJump errors;
  jpeg_compress_struct out;
  jpeg_decompress_struct in;
  unsigned char* bytes;  // the compressed picture (libjpeg's malloc)
  unsigned long size;
};

bool round_trip(Coder& c, std::uint8_t* pixels, int width, int height, int components, J_COLOR_SPACE space,
                int quality) {
  c.out.err = c.in.err = jpeg_jumping_errors(c.errors);
  if (setjmp(c.errors.jump)) {
    jpeg_destroy_compress(&c.out);  // each safe on a structure never created or destroyed
    jpeg_destroy_decompress(&c.in);
    return false;
  }
  jpeg_create_compress(&c.out);
  jpeg_mem_dest(&c.out, &c.bytes, &c.size);
  c.out.image_width = static_cast<JDIMENSION>(width);
  c.out.image_height = static_cast<JDIMENSION>(height);
  c.out.input_components = components;
  c.out.in_color_space = space;
  jpeg_set_defaults(&c.out);
  jpeg_set_quality(&c.out, quality, TRUE);
  jpeg_start_compress(&c.out, TRUE);
  const std::size_t stride = static_cast<std::size_t>(width) * static_cast<std::size_t>(components);
  while (c.out.next_scanline < c.out.image_height) {
    JSAMPROW row = pixels + c.out.next_scanline * stride;
    jpeg_write_scanlines(&c.out, &row, 1);
  }
  jpeg_finish_compress(&c.out);
  jpeg_destroy_compress(&c.out);
  jpeg_create_decompress(&c.in);
  jpeg_mem_src(&c.in, c.bytes, c.size);
  jpeg_read_header(&c.in, TRUE);
  c.in.out_color_space = space;
  jpeg_start_decompress(&c.in);
  while (c.in.output_scanline < c.in.output_height) {
    JSAMPROW row = pixels + c.in.output_scanline * stride;
    jpeg_read_scanlines(&c.in, &row, 1);
  }
  jpeg_finish_decompress(&c.in);
  jpeg_destroy_decompress(&c.in);
  return true;
}

}  // namespace

bool jpeg_round_trip(std::uint8_t* pixels, int width, int height, PixelFormat format, int quality, std::string& error) {
  if (format == PixelFormat::mono16)
    throw std::invalid_argument("jpeg=: 16-bit frames are not JPEG's (8-bit grey or colour)");
  const J_COLOR_SPACE space = format == PixelFormat::mono8  ? JCS_GRAYSCALE
                              : format == PixelFormat::rgb8 ? JCS_RGB
                                                            : JCS_EXT_BGR;
  Coder c{};
  const bool ok = round_trip(c, pixels, width, height, bytes_per_pixel(format), space, quality);
  std::free(c.bytes);
  if (!ok) error = c.errors.message;
  return ok;
}

}  // namespace ccdlane::cli
