// Grey pictures from JPEG (libjpeg), PNG and PGM (the frame readers).
#include "tools/ccdlane/grey_picture.hpp"

#include <jpeglib.h>

#include <csetjmp>
#include <cstdio>
#include <new>
#include <stdexcept>

#include "base/regular_file.hpp"
#include "drivers/frames/pgm.hpp"
#include "drivers/frames/picture_bounds.hpp"
#include "drivers/frames/png.hpp"

namespace ccdlane::cli {
namespace {

// A picture file of more is no calibration picture (a 40 MP PGM is 40 MB).
constexpr std::size_t kMaxPictureFileBytes = std::size_t{256} << 20;

struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void on_jpeg_error(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  (*info->err->format_message)(info, error->message);
  std::longjmp(error->jump, 1);
}

// libjpeg's part, in a frame of its own: nothing with a destructor lives here (a longjmp
// skips destructors; std::string work beside a setjmp is what -Wclobbered flags at -O1).
// Reads the picture's size from its header; with `pixels` (sized width x height by the
// caller) decodes it as grey into them. False with error.message when libjpeg fails.
bool run_libjpeg(const std::vector<unsigned char>& bytes, JpegError& error, int& width, int& height,
                 std::uint8_t* pixels) {
  jpeg_decompress_struct info{};
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = on_jpeg_error;
  if (setjmp(error.jump)) {
    jpeg_destroy_decompress(&info);
    return false;
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, bytes.data(), static_cast<unsigned long>(bytes.size()));
  jpeg_read_header(&info, TRUE);
  width = static_cast<int>(info.image_width);
  height = static_cast<int>(info.image_height);
  if (pixels) {
    info.out_color_space = JCS_GRAYSCALE;
    jpeg_start_decompress(&info);
    while (info.output_scanline < info.output_height) {
      JSAMPROW row = pixels + static_cast<std::size_t>(info.output_scanline) * static_cast<std::size_t>(width);
      jpeg_read_scanlines(&info, &row, 1);
    }
    jpeg_finish_decompress(&info);
  }
  jpeg_destroy_decompress(&info);
  return true;
}

// The header first: a 221-byte JPEG may claim 20000x20000 pixels, so the size is bounded
// before the output is sized; then the pixels, in a second pass over the bytes.
bool decode_jpeg(const std::vector<unsigned char>& bytes, GreyPicture& out, std::string& why) {
  JpegError error{};
  int width = 0, height = 0;
  if (!run_libjpeg(bytes, error, width, height, nullptr)) {
    why = error.message;
    return false;
  }
  why = picture_size_problem(width, height);
  if (!why.empty()) return false;
  out.width = width;
  out.height = height;
  out.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  if (!run_libjpeg(bytes, error, width, height, out.pixels.data())) {
    why = error.message;
    return false;
  }
  return true;
}

// Through the frame driver's PNG codec; colour to grey by its luma, as detection sees it.
void read_png_grey(const std::string& path, GreyPicture& out) {
  const OwnedPicture picture = read_png_picture(path);
  const ImageView view = picture.view();
  out.width = picture.width;
  out.height = picture.height;
  out.pixels.resize(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height));
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      out.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(out.width) + static_cast<std::size_t>(x)] =
          static_cast<std::uint8_t>(view.at(x, y));
}

void read_pgm(const std::string& path, std::size_t file_bytes, GreyPicture& out) {
  PgmReader reader;
  PgmHeader header;
  if (reader.probe(path.c_str(), header) != PgmFault::none) throw std::runtime_error(std::string(reader.error()));
  // A 35-byte header may claim 65535x65535: bounded, and held against the file's own size.
  if (const std::string why = picture_size_problem(header.width, header.height); !why.empty())
    throw std::runtime_error(path + ": " + why);
  if (header.raster_bytes() > file_bytes)
    throw std::runtime_error(path + ": truncated: its header says " + std::to_string(header.width) + "x" +
                             std::to_string(header.height) + " pixels, more than its " + std::to_string(file_bytes) +
                             " bytes can hold");
  const int bytes = header.bytes_per_sample();
  std::vector<std::uint8_t> raster(header.raster_bytes());
  const MutableImageView into{raster.data(),        header.width,    header.height,
                              header.width * bytes, header.format(), header.significant_bits()};
  if (reader.read(path.c_str(), into) != PgmFault::none) throw std::runtime_error(std::string(reader.error()));
  out.width = header.width;
  out.height = header.height;
  out.pixels.resize(static_cast<std::size_t>(header.width) * static_cast<std::size_t>(header.height));
  const ImageView view = into;
  for (int y = 0; y < header.height; ++y)
    for (int x = 0; x < header.width; ++x)
      out.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(header.width) + static_cast<std::size_t>(x)] =
          static_cast<std::uint8_t>(static_cast<long>(view.at(x, y)) * 255 / header.maxval);
}

GreyPicture read_grey_picture_bounded(const std::string& path) {
  // A regular file (a FIFO would block), of a size a picture has.
  std::string text;
  if (const int rc = read_regular_file(path, kMaxPictureFileBytes, text); rc < 0)
    throw std::runtime_error(path + ": cannot open the picture: " + regular_file_error(rc));
  const std::vector<unsigned char> bytes(text.begin(), text.end());
  GreyPicture out;
  std::string why;
  if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) {
    if (!decode_jpeg(bytes, out, why)) throw std::runtime_error(path + ": bad JPEG: " + why);
  } else if (bytes.size() >= 8 && bytes[0] == 0x89 && bytes[1] == 'P' && bytes[2] == 'N' && bytes[3] == 'G') {
    read_png_grey(path, out);
  } else if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '5') {
    read_pgm(path, bytes.size(), out);
  } else {
    throw std::runtime_error(path + ": not a JPEG, PNG or binary PGM picture");
  }
  return out;
}

}  // namespace

GreyPicture read_grey_picture(const std::string& path) {
  try {
    return read_grey_picture_bounded(path);
  } catch (const std::bad_alloc&) {  // the bounds leave room for a machine that is short of memory
    throw std::runtime_error(path + ": out of memory decoding the picture");
  }
}

}  // namespace ccdlane::cli
