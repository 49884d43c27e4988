// JPEG decode over libjpeg: its errors (a longjmp, jpeg_error_jump.hpp) are caught in one
// small function that holds nothing with a destructor; the checks around it are ordinary C++.
#include "drivers/frames/jpeg.hpp"

#include <jpeglib.h>
// After jpeglib.h, which it needs: the message codes (JWRN_JPEG_EOF).
#include <jerror.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "base/unique_fd.hpp"
#include "drivers/frames/jpeg_error_jump.hpp"
#include "drivers/frames/picture_bounds.hpp"

namespace ccdlane {
namespace {

// A frame's JPEG is a few hundred kB; a file larger than this is not a frame.
constexpr off_t kMaxFileBytes = off_t{64} << 20;

// Warnings (premature end of data among them) are remembered, not printed: a truncated
// file is reported by the reader as truncated.
void on_warning(j_common_ptr info, int level) {
  if (level >= 0) return;
  auto* e = reinterpret_cast<JpegErrorJump*>(info->err);
  if (info->err->msg_code == JWRN_JPEG_EOF) e->manager.num_warnings = -1;  // the data ended early
}

enum class JpegStep { ok, header_error, wrong_size, wrong_format, decode_error };

// libjpeg's part: nothing with a destructor lives here (a longjmp skips destructors).
JpegStep run_libjpeg(const std::uint8_t* data, std::size_t size, const MutableImageView* target, PgmHeader& header,
                     JpegErrorJump& error, int& rows_read) {
  jpeg_decompress_struct info{};
  info.err = jpeg_jumping_errors(error);
  error.manager.emit_message = on_warning;
  rows_read = 0;
  if (setjmp(error.jump)) {
    const bool in_header = info.global_state < 202;  // before DSTATE_READY: still in the header
    jpeg_destroy_decompress(&info);
    return in_header ? JpegStep::header_error : JpegStep::decode_error;
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
  jpeg_read_header(&info, TRUE);
  header.width = static_cast<int>(info.image_width);
  header.height = static_cast<int>(info.image_height);
  header.maxval = 255;
  header.channels = info.num_components == 1 ? 1 : 3;
  if (info.num_components != 1 && info.num_components != 3) {
    jpeg_destroy_decompress(&info);
    return JpegStep::wrong_format;
  }
  if (!target) {
    jpeg_destroy_decompress(&info);
    return JpegStep::ok;
  }
  const MutableImageView& into = *target;
  if (header.width != into.width || header.height != into.height) {
    jpeg_destroy_decompress(&info);
    return JpegStep::wrong_size;
  }
  const bool grey_frames = into.format == PixelFormat::mono8;
  if (!grey_frames && header.channels == 1) {  // colour frames from a grey picture: not the same camera
    jpeg_destroy_decompress(&info);
    return JpegStep::wrong_format;
  }
  info.out_color_space = grey_frames ? JCS_GRAYSCALE : JCS_RGB;  // libjpeg converts colour to grey exactly
  jpeg_start_decompress(&info);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = into.row(static_cast<int>(info.output_scanline));
    jpeg_read_scanlines(&info, &row, 1);
    ++rows_read;
  }
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);
  return JpegStep::ok;
}

}  // namespace

bool has_jpeg_extension(std::string_view path) {
  auto ends_with = [&](std::string_view ext) {
    if (path.size() < ext.size()) return false;
    for (std::size_t k = 0; k < ext.size(); ++k)
      if (std::tolower(static_cast<unsigned char>(path[path.size() - ext.size() + k])) != ext[k]) return false;
    return true;
  };
  return ends_with(".jpg") || ends_with(".jpeg");
}

PgmFault JpegReader::load(const char* path) {
  UniqueFd fd;
  struct stat st {};
  if (const PgmFault f = open_regular(path, fd, st); f != PgmFault::none) return f;
  if (st.st_size == 0) return fail(PgmFault::truncated, path, "truncated: the file is empty");
  if (st.st_size > kMaxFileBytes)
    return fail(PgmFault::bad_header, path, "bad header: %lld bytes is not a frame",
                static_cast<long long>(st.st_size));
  const auto size = static_cast<std::size_t>(st.st_size);
  if (file_.size() < size) file_.resize(size);
  std::size_t got = 0;
  while (got < size) {
    const ssize_t r = ::read(fd.get(), file_.data() + got, size - got);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return fail(PgmFault::unreadable, path, "read error: %s", std::strerror(errno));
    if (r == 0) break;
    got += static_cast<std::size_t>(r);
  }
  file_bytes_ = got;
  if (got < 2 || file_[0] != 0xFF || file_[1] != 0xD8)
    return fail(PgmFault::bad_header, path, "bad header: not a JPEG (no start-of-image marker)");
  return PgmFault::none;
}

PgmFault JpegReader::decode(const char* path, const MutableImageView* into, PgmHeader& header) {
  if (const PgmFault f = load(path); f != PgmFault::none) return f;
  JpegErrorJump error{};
  int rows = 0;
  const JpegStep step = run_libjpeg(file_.data(), file_bytes_, into, header, error, rows);
  switch (step) {
    case JpegStep::ok: break;
    case JpegStep::header_error: return fail(PgmFault::bad_header, path, "bad header: %s", error.message);
    case JpegStep::wrong_size:
      return fail(PgmFault::wrong_size, path, "wrong size: %dx%d, expected %dx%d", header.width, header.height,
                  into->width, into->height);
    case JpegStep::wrong_format:
      return fail(PgmFault::wrong_depth, path, "wrong format: %d channels, frames are %s", header.channels,
                  into ? (into->format == PixelFormat::mono8 ? "grey" : "colour") : "grey or colour");
    case JpegStep::decode_error:
      return fail(PgmFault::corrupt, path, "corrupt: %s (after %d of %d rows)", error.message, rows, header.height);
  }
  if (header.width > kMaxPictureDimension || header.height > kMaxPictureDimension)
    return fail(PgmFault::bad_header, path, "bad header: %dx%d is not a frame", header.width, header.height);
  if (error.manager.num_warnings < 0)
    return fail(PgmFault::truncated, path, "truncated: the data ends before the last row");
  clear_problem();
  return PgmFault::none;
}

PgmFault JpegReader::read(const char* path, const MutableImageView& into, PgmHeader* header_out) {
  PgmHeader h;
  const PgmFault f = decode(path, &into, h);
  if (f == PgmFault::none && header_out) *header_out = h;
  return f;
}

PgmFault JpegReader::probe(const char* path, PgmHeader& header) { return decode(path, nullptr, header); }

}  // namespace ccdlane
