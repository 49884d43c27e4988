// FFmpeg's error codes as text, for the one-line messages of the video reader and writer
// (internal to drivers/frames: includes FFmpeg's own header).
#pragma once

extern "C" {
#include <libavutil/error.h>
}

#include <string>

namespace ccdlane {

inline std::string av_error_text(int error) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(error, text, sizeof text);
  return text;
}

}  // namespace ccdlane
