// How large a picture the tools decode whole (calibration pictures, lane masks, PGM and
// PNG files): the size comes from the header and is checked before a byte of pixels is
// allocated, so a small file claiming a huge picture costs nothing.
#pragma once

#include <cstdint>
#include <string>

namespace ccdlane {

// The widest and tallest frame file (PGM, PNG, JPEG) read: 16-bit sizes, as cameras and
// the codecs' own limits have them. A header claiming more is damage.
inline constexpr int kMaxPictureDimension = 65535;

// 40 million pixels: an 8K frame (33 MP) with margin; grey it is 40 MB, colour 120 MB.
inline constexpr std::int64_t kMaxPicturePixels = 40'000'000;

// "" when a width x height picture may be decoded, else why not ("60000x60000 pixels:
// more than 40000000; not decoded").
std::string picture_size_problem(std::int64_t width, std::int64_t height, std::int64_t max_pixels = kMaxPicturePixels);

}  // namespace ccdlane
