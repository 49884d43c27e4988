// Why a frame file could not be read: one set of faults for every frame format (PGM,
// PPM, PNG), so that frame directories count and report them alike.
#pragma once

#include <cstdint>

namespace ccdlane {

// Why a frame file (PGM, PPM or PNG) could not be used.
enum class PgmFault : std::uint8_t {
  none,
  missing,      // no such file
  unreadable,   // exists but cannot be opened or read (permissions, I/O error)
  bad_header,   // not a binary PGM, or an impossible width, height or maxval
  wrong_size,   // width x height differ from the frames expected
  wrong_depth,  // 8-bit file for 16-bit frames or the other way round
  truncated,    // fewer raster bytes than the header promises
  corrupt,      // compressed frames (PNG): a checksum or the compressed data is wrong
};
const char* to_string(PgmFault f);

}  // namespace ccdlane
