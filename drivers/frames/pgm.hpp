// Binary PGM (P5) frames, 8-bit and 16-bit big-endian, and binary 8-bit PPM (P6) colour
// frames: decode into a caller's fixed buffer with a precise reason when a file is
// damaged, and write atomically.
//
// Hand-written rather than a general image library: replay and the daemon decode every
// frame into a buffer of the fixed pool without allocating, and a damaged file must be
// reported as exactly what is wrong with it (missing, truncated by N bytes, wrong size,
// bad header), not as a generic "cannot load".
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "base/image_view.hpp"
#include "drivers/frames/frame_file_problem.hpp"
#include "drivers/frames/pgm_fault.hpp"

namespace ccdlane {

// What the header of a frame file says (PGM, PPM; a PNG's is given in the same terms).
struct PgmHeader {
  int width = 0;
  int height = 0;
  int maxval = 0;          // 1..255: 8-bit samples, 256..65535: 16-bit big-endian
  std::size_t offset = 0;  // where the raster starts
  int channels = 1;        // 1: PGM (P5), 3: PPM (P6, 8-bit RGB only)
  int bytes_per_sample() const { return maxval > 255 ? 2 : 1; }
  PixelFormat format() const {
    return channels == 3 ? PixelFormat::rgb8 : maxval > 255 ? PixelFormat::mono16 : PixelFormat::mono8;
  }
  int significant_bits() const;  // bits needed for maxval
  std::size_t raster_bytes() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
           static_cast<std::size_t>(bytes_per_sample() * channels);
  }
};

// Parses a P5 or P6 header at the start of `bytes` (comments allowed between fields). Returns
// the fault and, when none, fills `header`. `why` (may be null) receives a short reason.
PgmFault parse_pgm_header(std::string_view bytes, PgmHeader& header, std::string_view* why = nullptr);

// Decodes PGM files into caller-provided buffers. Owns only a fixed message buffer: a
// read opens the file, reads straight into the destination rows, and allocates nothing.
class PgmReader : public FrameFileProblem {
 public:
  // Decodes `path` into `into` (whose width, height and format are what the frames must
  // be). On success the header read is returned through `header` (if not null). 16-bit
  // samples are converted to native byte order.
  PgmFault read(const char* path, const MutableImageView& into, PgmHeader* header = nullptr);

  // Reads only the header (to learn a directory's frame size and depth).
  PgmFault probe(const char* path, PgmHeader& header);

  // error(): "<path>: <reason>" of the last fault (FrameFileProblem).

 private:
  PgmFault open_and_parse(const char* path, int& fd, PgmHeader& header, long long& file_size);
};

// Writes `image` as a binary PGM: 8-bit (maxval 255) or 16-bit big-endian (maxval
// 2^significant_bits - 1); a colour image (rgb8 or bgr8) as an 8-bit PPM (P6, RGB). Written under a temporary name in
// the same directory and renamed into place, so a failure never leaves a partial file. Throws std::runtime_error naming
// the file and the reason.
void write_pgm(const std::string& path, const ImageView& image);

}  // namespace ccdlane
