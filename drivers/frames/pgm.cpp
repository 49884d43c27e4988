// Binary PGM decode/encode with POSIX calls only: the read path opens the file, reads the
// header into a stack buffer and the raster straight into the destination rows.
#include "drivers/frames/pgm.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "base/temp_file.hpp"
#include "base/unique_fd.hpp"
#include "drivers/frames/picture_bounds.hpp"

namespace ccdlane {
namespace {

constexpr std::size_t kMaxHeaderBytes = 4096;  // room for generous comments

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

// Reads exactly `n` bytes at `offset` unless the file ends: returns bytes read, or -errno.
long long read_fully(int fd, std::uint8_t* dst, std::size_t n, long long offset) {
  std::size_t done = 0;
  while (done < n) {
    const ssize_t r = ::pread(fd, dst + done, n - done, static_cast<off_t>(offset) + static_cast<off_t>(done));
    if (r < 0) {
      if (errno == EINTR) continue;
      return -errno;
    }
    if (r == 0) break;
    done += static_cast<std::size_t>(r);
  }
  return static_cast<long long>(done);
}

// A header field: skips whitespace and comments, then reads a decimal number.
struct HeaderCursor {
  std::string_view bytes;
  std::size_t pos = 0;

  // Returns false at the end of `bytes` (the header did not fit or the file ended).
  bool skip_space_and_comments() {
    while (pos < bytes.size()) {
      if (is_space(bytes[pos])) {
        ++pos;
      } else if (bytes[pos] == '#') {
        while (pos < bytes.size() && bytes[pos] != '\n' && bytes[pos] != '\r') ++pos;
      } else {
        return true;
      }
    }
    return false;
  }

  enum class Field { ok, end, not_a_number, too_large };
  Field number(int& out) {
    if (!skip_space_and_comments()) return Field::end;
    if (bytes[pos] < '0' || bytes[pos] > '9') return Field::not_a_number;
    long long v = 0;
    while (pos < bytes.size() && bytes[pos] >= '0' && bytes[pos] <= '9') {
      v = v * 10 + (bytes[pos] - '0');
      if (v > kMaxPictureDimension) return Field::too_large;
      ++pos;
    }
    if (pos >= bytes.size()) return Field::end;  // the number may go on past what we have
    out = static_cast<int>(v);
    return Field::ok;
  }
};

}  // namespace

const char* to_string(PgmFault f) {
  switch (f) {
    case PgmFault::none: return "ok";
    case PgmFault::missing: return "missing";
    case PgmFault::unreadable: return "unreadable";
    case PgmFault::bad_header: return "bad header";
    case PgmFault::wrong_size: return "wrong size";
    case PgmFault::wrong_depth: return "wrong depth";
    case PgmFault::truncated: return "truncated";
    case PgmFault::corrupt: return "corrupt";
  }
  return "?";
}

int PgmHeader::significant_bits() const {
  int bits = 1;
  while ((1 << bits) - 1 < maxval) ++bits;
  return bits;
}

PgmFault parse_pgm_header(std::string_view bytes, PgmHeader& header, std::string_view* why) {
  auto bad = [&](std::string_view reason) {
    if (why) *why = reason;
    return PgmFault::bad_header;
  };
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '5' && bytes[1] != '6')) {
    if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '2') return bad("ASCII PGM (P2); only binary P5 is read");
    if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '3') return bad("ASCII PPM (P3); only binary P6 is read");
    return bad("not a binary PGM or PPM (no P5 or P6 magic number)");
  }
  const bool ppm = bytes[1] == '6';
  HeaderCursor cur{bytes, 2};
  if (cur.pos < bytes.size() && !is_space(bytes[cur.pos]) && bytes[cur.pos] != '#')
    return bad(ppm ? "no whitespace after the P6 magic number" : "no whitespace after the P5 magic number");
  int fields[3] = {0, 0, 0};
  static constexpr std::string_view kZero[3] = {"width is 0", "height is 0", "maxval is 0"};
  static constexpr std::string_view kMissing[3] = {"header ends before the width", "header ends before the height",
                                                   "header ends before the maxval"};
  static constexpr std::string_view kNotNumber[3] = {"width is not a number", "height is not a number",
                                                     "maxval is not a number"};
  for (int i = 0; i < 3; ++i) {
    switch (cur.number(fields[i])) {
      case HeaderCursor::Field::ok: break;
      case HeaderCursor::Field::end: return bad(kMissing[i]);
      case HeaderCursor::Field::not_a_number: return bad(kNotNumber[i]);
      case HeaderCursor::Field::too_large: return bad(i == 2 ? "maxval above 65535" : "width or height above 65535");
    }
    if (fields[i] == 0) return bad(kZero[i]);
  }
  // Exactly one whitespace byte separates maxval from the raster (which may start with
  // bytes that look like whitespace).
  if (!is_space(bytes[cur.pos])) return bad("no whitespace after the maxval");
  if (ppm && fields[2] > 255) return bad("16-bit PPM (maxval above 255); only 8-bit colour is read");
  header.channels = ppm ? 3 : 1;
  header.width = fields[0];
  header.height = fields[1];
  header.maxval = fields[2];
  header.offset = cur.pos + 1;
  if (why) *why = {};
  return PgmFault::none;
}

PgmFault PgmReader::open_and_parse(const char* path, int& fd_out, PgmHeader& header, long long& file_size) {
  fd_out = -1;
  UniqueFd fd;
  struct stat st {};
  if (const PgmFault f = open_regular(path, fd, st); f != PgmFault::none) return f;
  file_size = st.st_size;
  std::uint8_t head[kMaxHeaderBytes];
  const long long got = read_fully(fd.get(), head, sizeof head, 0);
  if (got < 0) return fail(PgmFault::unreadable, path, "read error: %s", std::strerror(static_cast<int>(-got)));
  if (got == 0) return fail(PgmFault::truncated, path, "truncated: the file is empty");
  std::string_view why;
  const std::string_view bytes(reinterpret_cast<const char*>(head), static_cast<std::size_t>(got));
  if (parse_pgm_header(bytes, header, &why) != PgmFault::none) {
    if (static_cast<std::size_t>(got) == sizeof head && why.substr(0, 11) == "header ends")
      return fail(PgmFault::bad_header, path, "bad header: longer than %zu bytes", kMaxHeaderBytes);
    return fail(PgmFault::bad_header, path, "bad header: %.*s", static_cast<int>(why.size()), why.data());
  }
  fd_out = fd.release();
  return PgmFault::none;
}

PgmFault PgmReader::probe(const char* path, PgmHeader& header) {
  int raw = -1;
  long long size = 0;
  const PgmFault f = open_and_parse(path, raw, header, size);
  UniqueFd fd(raw);
  if (f != PgmFault::none) return f;
  clear_problem();
  return PgmFault::none;
}

PgmFault PgmReader::read(const char* path, const MutableImageView& into, PgmHeader* header_out) {
  int raw = -1;
  long long file_size = 0;
  PgmHeader h;
  const PgmFault f = open_and_parse(path, raw, h, file_size);
  UniqueFd fd(raw);
  if (f != PgmFault::none) return f;
  if (h.width != into.width || h.height != into.height)
    return fail(PgmFault::wrong_size, path, "wrong size: %dx%d, expected %dx%d", h.width, h.height, into.width,
                into.height);
  if (h.format() != into.format) {
    const auto kind = [](PixelFormat pf) {
      return pf == PixelFormat::mono16 ? "16-bit grey" : pf == PixelFormat::mono8 ? "8-bit grey" : "colour";
    };
    return fail(PgmFault::wrong_depth, path, "wrong depth: %s %s (maxval %d), expected %s frames", kind(h.format()),
                h.channels == 3 ? "PPM" : "PGM", h.maxval, kind(into.format));
  }
  const long long need = static_cast<long long>(h.offset + h.raster_bytes());
  if (file_size < need)
    return fail(PgmFault::truncated, path, "truncated: %lld of %zu raster bytes",
                std::max(0LL, file_size - static_cast<long long>(h.offset)), h.raster_bytes());

  const std::size_t row_bytes =
      static_cast<std::size_t>(h.width) * static_cast<std::size_t>(h.bytes_per_sample() * h.channels);
  long long offset = static_cast<long long>(h.offset);
  if (into.stride_bytes == static_cast<std::ptrdiff_t>(row_bytes)) {
    const long long got = read_fully(fd.get(), into.data, h.raster_bytes(), offset);
    if (got < 0) return fail(PgmFault::unreadable, path, "read error: %s", std::strerror(static_cast<int>(-got)));
    if (got != static_cast<long long>(h.raster_bytes()))
      return fail(PgmFault::truncated, path, "truncated: %lld of %zu raster bytes", got, h.raster_bytes());
  } else {
    for (int y = 0; y < h.height; ++y, offset += static_cast<long long>(row_bytes)) {
      const long long got = read_fully(fd.get(), into.row(y), row_bytes, offset);
      if (got < 0) return fail(PgmFault::unreadable, path, "read error: %s", std::strerror(static_cast<int>(-got)));
      if (got != static_cast<long long>(row_bytes))
        return fail(PgmFault::truncated, path, "truncated in row %d", y + 1);
    }
  }
  if (h.bytes_per_sample() == 2) {
    for (int y = 0; y < h.height; ++y) {
      std::uint8_t* p = into.row(y);
      for (int x = 0; x < h.width; ++x) {
        const std::uint16_t v = static_cast<std::uint16_t>((p[2 * x] << 8) | p[2 * x + 1]);
        std::memcpy(p + 2 * x, &v, 2);
      }
    }
  }
  if (header_out) *header_out = h;
  clear_problem();
  return PgmFault::none;
}

void write_pgm(const std::string& path, const ImageView& image) {
  if (image.empty()) throw std::runtime_error(path + ": cannot write an empty image");
  const bool wide = image.format == PixelFormat::mono16;
  const bool colour = is_colour(image.format);
  const int bits = wide ? std::clamp(image.significant_bits, 9, 16) : 8;
  const int maxval = wide ? (1 << bits) - 1 : 255;
  char header[64];
  const int header_len =
      std::snprintf(header, sizeof header, "%s\n%d %d\n%d\n", colour ? "P6" : "P5", image.width, image.height, maxval);
  const std::size_t row_bytes = static_cast<std::size_t>(image.width) * (wide ? 2u : colour ? 3u : 1u);
  std::vector<std::uint8_t> data(static_cast<std::size_t>(header_len) +
                                 row_bytes * static_cast<std::size_t>(image.height));
  std::memcpy(data.data(), header, static_cast<std::size_t>(header_len));
  std::uint8_t* out = data.data() + header_len;
  for (int y = 0; y < image.height; ++y, out += row_bytes) {
    const std::uint8_t* row = image.row(y);
    if (image.format == PixelFormat::bgr8) {
      for (int x = 0; x < image.width; ++x) {
        out[3 * x] = row[3 * x + 2];
        out[3 * x + 1] = row[3 * x + 1];
        out[3 * x + 2] = row[3 * x];
      }
      continue;
    }
    if (!wide) {
      std::memcpy(out, row, row_bytes);
      continue;
    }
    for (int x = 0; x < image.width; ++x) {
      std::uint16_t v;
      std::memcpy(&v, row + 2 * x, 2);
      out[2 * x] = static_cast<std::uint8_t>(v >> 8);
      out[2 * x + 1] = static_cast<std::uint8_t>(v & 0xff);
    }
  }

  char tmp_name[PATH_MAX];
  UniqueFd fd(create_temp_beside(path.c_str(), tmp_name, sizeof tmp_name));
  if (fd.get() < 0)
    throw std::runtime_error(path + ": cannot create a temporary beside it: " + std::strerror(-fd.get()));
  const std::string tmp = tmp_name;
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t w = ::write(fd.get(), data.data() + done, data.size() - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      const std::string reason = w < 0 ? std::strerror(errno) : "nothing written";
      ::unlink(tmp.c_str());
      throw std::runtime_error(tmp + ": write failed: " + reason);
    }
    done += static_cast<std::size_t>(w);
  }
  if (::close(fd.release()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error(tmp + ": write failed: " + reason);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename into place: " + reason);
  }
}

}  // namespace ccdlane
