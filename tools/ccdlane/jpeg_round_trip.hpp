// A picture through a JPEG encoder and back, as a dashcam's, a video stream's or a
// dataset's compression leaves it (blocks, ringing at edges, colour at a quarter of the
// pixels): the `jpeg=QUALITY` picture condition of `ccdlane replay --condition`.
#pragma once

#include <string>

#include "base/image_view.hpp"

namespace ccdlane::cli {

// Compresses the 8-bit grey or colour picture `pixels` (width x height, rows packed, in
// `format`) with libjpeg's defaults at `quality` (1-100; colour with its chroma at half
// the resolution each way, as libjpeg, cameras and datasets do) and decodes it back into
// `pixels`. False, with libjpeg's message in `error`, when libjpeg fails; a 16-bit
// picture is not JPEG's and throws std::invalid_argument.
bool jpeg_round_trip(std::uint8_t* pixels, int width, int height, PixelFormat format, int quality, std::string& error);

}  // namespace ccdlane::cli
