// Makes a camera FrameSource from a source string as users write it: "v4l2:/dev/video0"
// or "aravis:ID" (ID: an IP address, a camera id or serial, or Fake_1).
#pragma once

#include <memory>
#include <string>

#include "drivers/camera/camera_settings.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

// Not yet opened. Throws std::invalid_argument, saying why, for a string of no known
// kind (a start-up error: the caller reports it as bad input).
std::unique_ptr<FrameSource> make_camera(const std::string& source, const CameraSettings& settings);

}  // namespace ccdlane
