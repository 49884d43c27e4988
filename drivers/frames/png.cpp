// PNG decode/encode over libpng: the reader hands libpng a fixed arena and a fixed file
// buffer; libpng's errors (a longjmp) are caught in two small functions that hold nothing
// with a destructor.
#include "drivers/frames/png.hpp"

#include <fcntl.h>
#include <png.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <csetjmp>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <new>
#include <stdexcept>

#include "base/temp_file.hpp"
#include "base/unique_fd.hpp"
#include "drivers/frames/picture_bounds.hpp"

namespace ccdlane {
namespace {

// libpng's structures, zlib's inflate state and 32 KiB window, and two rows of at most
// 65535 RGBA pixels (libpng sizes its row buffers for the widest step of a transform).
constexpr std::size_t kArenaBytes = std::size_t{1} << 20;
constexpr std::size_t kFileBufferBytes = 64 * 1024;
constexpr std::size_t kAlign = 16;
// Ancillary chunks a frame does not use: skipped unread rather than decoded into memory.
constexpr png_byte kIgnoredChunks[] =
    "iCCP\0iTXt\0tEXt\0zTXt\0sPLT\0eXIf\0tIME\0pHYs\0sBIT\0hIST\0bKGD\0cHRM\0sRGB\0gAMA\0";

}  // namespace

struct PngReader::Decoder {
  // The arena: a bump allocator that gives back only its latest block (libpng frees in
  // roughly the reverse order it allocates), emptied before each file.
  std::unique_ptr<std::uint8_t[]> arena{new std::uint8_t[kArenaBytes + kAlign]};
  std::size_t used = 0, last = 0, peak = 0;
  // The file, read through a fixed buffer.
  int fd = -1;
  std::unique_ptr<std::uint8_t[]> buffer{new std::uint8_t[kFileBufferBytes]};
  std::size_t buffer_pos = 0, buffer_len = 0;
  long long consumed = 0;  // bytes handed to libpng
  bool ended = false;      // the file ended before libpng had what it asked for
  int read_errno = 0;
  int row = -1;  // the row being decoded (-1: still in the header)
  char message[200] = {};

  std::uint8_t* base() {
    const auto p = reinterpret_cast<std::uintptr_t>(arena.get());
    return arena.get() + ((kAlign - p % kAlign) % kAlign);
  }
  void reset() {
    used = last = 0;
    buffer_pos = buffer_len = 0;
    consumed = 0;
    ended = false;
    read_errno = 0;
    row = -1;
    message[0] = '\0';
  }
};

namespace {

using Decoder = PngReader::Decoder;

png_voidp arena_malloc(png_structp png, png_alloc_size_t size) {
  auto* d = static_cast<Decoder*>(png_get_mem_ptr(png));
  const std::size_t rounded = (size + kAlign - 1) / kAlign * kAlign;
  if (rounded < size || rounded > kArenaBytes - d->used) return nullptr;  // libpng reports "Out of memory"
  d->last = d->used;
  d->used += rounded;
  d->peak = std::max(d->peak, d->used);
  return d->base() + d->last;
}

void arena_free(png_structp png, png_voidp ptr) {
  auto* d = static_cast<Decoder*>(png_get_mem_ptr(png));
  if (ptr == d->base() + d->last) d->used = d->last;
}

[[noreturn]] void on_error(png_structp png, png_const_charp message) {
  if (auto* d = static_cast<Decoder*>(png_get_error_ptr(png)))
    std::snprintf(d->message, sizeof d->message, "%s", message);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // benign: the picture is still usable

void read_from_file(png_structp png, png_bytep out, png_size_t n) {
  auto* d = static_cast<Decoder*>(png_get_io_ptr(png));
  while (n > 0) {
    if (d->buffer_pos == d->buffer_len) {
      const ssize_t r = ::read(d->fd, d->buffer.get(), kFileBufferBytes);
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) {
        d->read_errno = errno;
        png_error(png, "read error");
      }
      if (r == 0) {
        d->ended = true;
        png_error(png, "the file ends early");
      }
      d->buffer_pos = 0;
      d->buffer_len = static_cast<std::size_t>(r);
    }
    const std::size_t take = std::min(n, d->buffer_len - d->buffer_pos);
    std::memcpy(out, d->buffer.get() + d->buffer_pos, take);
    d->buffer_pos += take;
    d->consumed += static_cast<long long>(take);
    out += take;
    n -= take;
  }
}

// What the libpng part of a decode came to.
enum class PngStep { ok, libpng_error, sixteen_bit, wrong_size, wrong_format, unexpected_layout };

// All of libpng's work on one file. It may longjmp back into this frame: everything
// here is plain data, set before setjmp or not used after a jump.
PngStep run_libpng(Decoder& d, const MutableImageView* into, PgmHeader& header, int& bit_depth) {
  png_structp png =
      png_create_read_struct_2(PNG_LIBPNG_VER_STRING, &d, on_error, on_warning, &d, arena_malloc, arena_free);
  if (!png) return PngStep::libpng_error;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    return PngStep::libpng_error;
  }
  png_set_user_limits(png, kMaxPictureDimension, kMaxPictureDimension);
  png_set_chunk_malloc_max(png, 256 * 1024);
  png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, nullptr, 0);
  png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, kIgnoredChunks,
                              static_cast<int>((sizeof kIgnoredChunks - 1) / 5));
  png_set_read_fn(png, &d, read_from_file);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);

  const int colour_type = png_get_color_type(png, info);
  bit_depth = png_get_bit_depth(png, info);
  header.width = static_cast<int>(png_get_image_width(png, info));
  header.height = static_cast<int>(png_get_image_height(png, info));
  header.maxval = 255;
  header.offset = 0;
  header.channels = (colour_type & PNG_COLOR_MASK_COLOR) != 0 ? 3 : 1;
  PngStep step = PngStep::ok;
  if (bit_depth > 8)
    step = PngStep::sixteen_bit;
  else if (into && (into->width != header.width || into->height != header.height))
    step = PngStep::wrong_size;
  else if (into && into->format != header.format())
    step = PngStep::wrong_format;
  if (step != PngStep::ok || !into) {
    png_destroy_read_struct(&png, &info, nullptr);
    return step;
  }
  if (colour_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colour_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if ((colour_type & PNG_COLOR_MASK_ALPHA) != 0 || png_get_valid(png, info, PNG_INFO_tRNS) != 0)
    png_set_strip_alpha(png);
  const int passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != static_cast<png_size_t>(header.width) * static_cast<png_size_t>(header.channels)) {
    png_destroy_read_struct(&png, &info, nullptr);
    return PngStep::unexpected_layout;
  }
  for (int pass = 0; pass < passes; ++pass)
    for (int y = 0; y < header.height; ++y) {
      d.row = y;
      png_read_row(png, into->row(y), nullptr);
    }
  d.row = header.height;  // what follows the rows: the last checksums, IEND
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return PngStep::ok;
}

struct WriteTarget {
  int fd = -1;
  int write_errno = 0;
  char message[200] = {};
};

[[noreturn]] void on_write_error(png_structp png, png_const_charp message) {
  if (auto* t = static_cast<WriteTarget*>(png_get_error_ptr(png)))
    std::snprintf(t->message, sizeof t->message, "%s", message);
  png_longjmp(png, 1);
}

void write_to_file(png_structp png, png_bytep data, png_size_t n) {
  auto* t = static_cast<WriteTarget*>(png_get_io_ptr(png));
  while (n > 0) {
    const ssize_t w = ::write(t->fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      t->write_errno = w < 0 ? errno : ENOSPC;
      png_error(png, "write failed");
    }
    data += w;
    n -= static_cast<png_size_t>(w);
  }
}

void flush_nothing(png_structp) {}

// libpng's encoding of one picture; longjmp-safe as run_libpng.
bool encode(WriteTarget& t, const ImageView& image, int zlib_level) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &t, on_write_error, on_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_set_write_fn(png, &t, write_to_file, flush_nothing);
  png_set_compression_level(png, zlib_level);
  // Fast levels: one cheap filter (most of the gain on camera pictures at a fraction of
  // the adaptive choice's time).
  if (zlib_level <= 2) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  const bool colour = is_colour(image.format);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               colour ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (image.format == PixelFormat::bgr8) png_set_bgr(png);
  for (int y = 0; y < image.height; ++y) png_write_row(png, image.row(y));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

PngReader::PngReader() : decoder_(std::make_unique<Decoder>()) {}
PngReader::~PngReader() = default;

std::size_t PngReader::peak_arena_bytes() const { return decoder_->peak; }

PgmFault PngReader::probe(const char* path, PgmHeader& header) { return decode(path, nullptr, header); }

PgmFault PngReader::read(const char* path, const MutableImageView& into, PgmHeader* header_out) {
  PgmHeader h;
  const PgmFault f = decode(path, &into, h);
  if (f == PgmFault::none && header_out) *header_out = h;
  return f;
}

PgmFault PngReader::decode(const char* path, const MutableImageView* into, PgmHeader& header) {
  Decoder& d = *decoder_;
  d.reset();
  UniqueFd fd;
  struct stat st {};
  if (const PgmFault f = open_regular(path, fd, st); f != PgmFault::none) return f;
  if (st.st_size == 0) return fail(PgmFault::truncated, path, "truncated: the file is empty");
  d.fd = fd.get();
  std::uint8_t signature[8];
  std::size_t got = 0;
  while (got < sizeof signature) {
    const ssize_t r = ::read(d.fd, signature + got, sizeof signature - got);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return fail(PgmFault::unreadable, path, "read error: %s", std::strerror(errno));
    if (r == 0) break;
    got += static_cast<std::size_t>(r);
  }
  if (got < sizeof signature || png_sig_cmp(signature, 0, sizeof signature) != 0)
    return fail(PgmFault::bad_header, path, "bad header: not a PNG (no PNG signature)");
  d.consumed = 8;

  int bit_depth = 8;
  const PngStep step = run_libpng(d, into, header, bit_depth);
  switch (step) {
    case PngStep::ok: clear_problem(); return PgmFault::none;
    case PngStep::sixteen_bit:
      return fail(PgmFault::wrong_depth, path,
                  "wrong depth: %d-bit PNG; only 8-bit PNG frames are read (16-bit frames are PGM)", bit_depth);
    case PngStep::wrong_size:
      return fail(PgmFault::wrong_size, path, "wrong size: %dx%d, expected %dx%d", header.width, header.height,
                  into->width, into->height);
    case PngStep::wrong_format:
      return fail(PgmFault::wrong_depth, path, "wrong depth: %s PNG, expected %s frames",
                  header.channels == 3 ? "colour" : "8-bit grey",
                  into->format == PixelFormat::mono16 ? "16-bit grey"
                  : is_colour(into->format)           ? "colour"
                                                      : "8-bit grey");
    case PngStep::unexpected_layout:
      return fail(PgmFault::bad_header, path, "bad header: a PNG layout this reader cannot decode");
    case PngStep::libpng_error: break;
  }
  if (d.read_errno != 0) return fail(PgmFault::unreadable, path, "read error: %s", std::strerror(d.read_errno));
  if (d.ended) {
    if (d.row < 0)
      return fail(PgmFault::truncated, path, "truncated: the file ends in the header, after %lld bytes", d.consumed);
    if (d.row < header.height)
      return fail(PgmFault::truncated, path, "truncated: the file ends after %lld bytes, in row %d of %d", d.consumed,
                  d.row + 1, header.height);
    return fail(PgmFault::truncated, path, "truncated: the file ends after %lld bytes, after the last row", d.consumed);
  }
  if (d.row < 0) return fail(PgmFault::bad_header, path, "bad header: %s", d.message);
  return fail(PgmFault::corrupt, path, "corrupt: %s (row %d of %d)", d.message, std::min(d.row + 1, header.height),
              header.height);
}

void write_png(const std::string& path, const ImageView& image, int zlib_level) {
  if (image.empty()) throw std::runtime_error(path + ": cannot write an empty image");
  if (image.format == PixelFormat::mono16)
    throw std::runtime_error(path + ": 16-bit frames are written as PGM, not PNG");
  char tmp_name[PATH_MAX];
  UniqueFd fd(create_temp_beside(path.c_str(), tmp_name, sizeof tmp_name));
  if (fd.get() < 0)
    throw std::runtime_error(path + ": cannot create a temporary beside it: " + std::strerror(-fd.get()));
  const std::string tmp = tmp_name;
  WriteTarget target;
  target.fd = fd.get();
  const bool encoded = encode(target, image, std::clamp(zlib_level, 0, 9));
  const int closed = ::close(fd.release());
  const int close_errno = errno;
  if (!encoded || closed != 0) {
    ::unlink(tmp.c_str());
    const std::string reason = target.write_errno ? std::strerror(target.write_errno)
                               : !encoded         ? std::string(target.message)
                                                  : std::strerror(close_errno);
    throw std::runtime_error(tmp + ": write failed: " + reason);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename into place: " + reason);
  }
}

OwnedPicture read_png_picture(const std::string& path) {
  PngReader reader;
  PgmHeader header;
  if (reader.probe(path.c_str(), header) != PgmFault::none) throw std::runtime_error(std::string(reader.error()));
  // The header's size, bounded before anything is allocated: a small file may claim a huge picture.
  if (const std::string why = picture_size_problem(header.width, header.height); !why.empty())
    throw std::runtime_error(path + ": " + why);
  OwnedPicture out;
  out.width = header.width;
  out.height = header.height;
  out.format = header.format();
  try {
    out.pixels.resize(static_cast<std::size_t>(out.stride()) * static_cast<std::size_t>(out.height));
  } catch (const std::bad_alloc&) {
    throw std::runtime_error(path + ": out of memory for its " + std::to_string(out.width) + "x" +
                             std::to_string(out.height) + " pixels");
  }
  if (reader.read(path.c_str(), out.mutable_view()) != PgmFault::none)
    throw std::runtime_error(std::string(reader.error()));
  return out;
}

bool has_png_extension(std::string_view path) {
  if (path.size() < 4) return false;
  const std::string_view ext = path.substr(path.size() - 4);
  return ext[0] == '.' && (ext[1] | 0x20) == 'p' && (ext[2] | 0x20) == 'n' && (ext[3] | 0x20) == 'g';
}

}  // namespace ccdlane
