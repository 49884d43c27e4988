// PNG frames (8-bit grey and 8-bit RGB): decoded into a caller's fixed buffer without
// allocating, with the same faults and reasons as PGM frames, and written atomically.
// The one PNG codec of the tree: tools and tests read and write their pictures here too.
//
// libpng does the decoding, but every byte it needs comes from an arena the reader owns
// (sized once at construction), and the file is read through a fixed buffer: a frame
// directory of PNG frames replays without touching the heap, as one of PGM frames does.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/image_view.hpp"
#include "drivers/frames/pgm.hpp"

namespace ccdlane {

// What a frame PNG is turned into: 8-bit grey (also 1, 2 and 4-bit grey, and grey with
// alpha) becomes mono8; RGB, RGB with alpha and palette pictures become rgb8. Alpha
// (and a tRNS transparency) is dropped: a camera frame has no use for it. 16-bit PNGs
// are refused (wrong_depth): 16-bit frames are written as PGM.
class PngReader : public FrameFileProblem {
 public:
  PngReader();
  ~PngReader();
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;

  // Decodes `path` into `into` (whose width, height and format are what the frames must
  // be). The header read is returned through `header` (maxval 255, channels 1 or 3).
  // Faults as PgmReader's: missing, unreadable, bad_header (no PNG signature, a damaged
  // header), wrong_size, wrong_depth (colour for grey frames, 16-bit), truncated (the
  // file ends early), corrupt (a checksum or the compressed data is wrong).
  PgmFault read(const char* path, const MutableImageView& into, PgmHeader* header = nullptr);

  // Reads only the header (to learn a directory's frame size and format).
  PgmFault probe(const char* path, PgmHeader& header);

  // error(): "<path>: <reason>" of the last fault (FrameFileProblem).

  // The most arena memory one decode needed so far (libpng's structures, zlib's window,
  // two rows), for sizing; a file needing more than the arena is refused as bad_header.
  std::size_t peak_arena_bytes() const;

  struct Decoder;  // libpng's state for one file; in png.cpp

 private:
  PgmFault decode(const char* path, const MutableImageView* into, PgmHeader& header);

  std::unique_ptr<Decoder> decoder_;
};

// Writes `image` as a PNG: mono8 as 8-bit grey, rgb8 and bgr8 as 8-bit RGB. Written under
// a temporary name in the same directory and renamed into place, so a failure never
// leaves a partial file. `zlib_level` 1 (the default, the fastest that compresses) takes
// ~30 ms of one core for a 1280x720 colour road picture, 0 ~7 ms (stored, no
// compression), 6 (zlib's usual trade-off) ~200 ms (tests/bench/frame_io_bench).
// Throws std::runtime_error naming the file and the reason. Allocates (not for the
// per-frame path of the daemon).
void write_png(const std::string& path, const ImageView& image, int zlib_level = 1);

// A whole picture read into memory, for tools and tests (allocates): mono8 or rgb8 as
// PngReader turns it. Throws std::runtime_error "<path>: <reason>".
struct OwnedPicture {
  std::vector<std::uint8_t> pixels;
  int width = 0, height = 0;
  PixelFormat format = PixelFormat::mono8;

  std::ptrdiff_t stride() const { return static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(format); }
  ImageView view() const { return {pixels.data(), width, height, stride(), format, 8}; }
  MutableImageView mutable_view() { return {pixels.data(), width, height, stride(), format, 8}; }
};
OwnedPicture read_png_picture(const std::string& path);

// True when `path` names a PNG by its extension (".png", any case): how a frame
// directory tells its PNG frames from PGM and PPM ones.
bool has_png_extension(std::string_view path);

}  // namespace ccdlane
