// JPEG frames (8-bit grey and colour, as cameras, datasets and dashcam stills give them):
// decoded by libjpeg into a caller's fixed buffer, with the same faults and reasons as
// PGM and PNG frames, so that a folder of benchmark pictures replays as a frame directory.
//
// The header is read and checked against the frames expected before anything is
// decoded: a small file claiming a huge picture costs nothing. libjpeg allocates its own
// working memory per picture (its memory manager is malloc); the file is read into a
// buffer that grows to the largest file and is then reused. JPEG frames are for replay
// and tools; the daemon's allocation-free recordings are PGM or PNG.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "base/image_view.hpp"
#include "drivers/frames/frame_file_problem.hpp"
#include "drivers/frames/pgm.hpp"

namespace ccdlane {

// Grey JPEGs become mono8, colour ones (YCbCr, RGB) rgb8; CMYK pictures are refused
// (wrong_depth), as are 12-bit ones (libjpeg-turbo's default build decodes 8-bit only).
class JpegReader : public FrameFileProblem {
 public:
  // Decodes `path` into `into` (width, height and format are what the frames must be).
  // Faults: missing, unreadable, bad_header (no JPEG start, a damaged header),
  // wrong_size, wrong_depth (colour for grey frames or grey for colour ones),
  // truncated (the data ends before the last row), corrupt (libjpeg's other errors).
  PgmFault read(const char* path, const MutableImageView& into, PgmHeader* header = nullptr);

  // Reads only the header (to learn a directory's frame size and format).
  PgmFault probe(const char* path, PgmHeader& header);

 private:
  PgmFault decode(const char* path, const MutableImageView* into, PgmHeader& header);
  PgmFault load(const char* path);

  std::vector<std::uint8_t> file_;  // the last file's bytes
  std::size_t file_bytes_ = 0;
};

// True when `path` names a JPEG by its extension (".jpg" or ".jpeg", any case).
bool has_jpeg_extension(std::string_view path);

}  // namespace ccdlane
