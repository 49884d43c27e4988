// The one place that knows which driver a source string names.
#include "drivers/camera/camera_factory.hpp"

#include <stdexcept>

#include "drivers/camera/aravis_camera.hpp"
#include "drivers/camera/v4l2_camera.hpp"

namespace ccdlane {

std::unique_ptr<FrameSource> make_camera(const std::string& source, const CameraSettings& settings) {
  const auto colon = source.find(':');
  const std::string kind = source.substr(0, colon);
  const std::string where = colon == std::string::npos ? "" : source.substr(colon + 1);
  if (colon == std::string::npos || (kind != "v4l2" && kind != "aravis")) {
    throw std::invalid_argument("source \"" + source + "\": expected v4l2:/dev/videoN or aravis:ID");
  }
  if (where.empty()) {
    throw std::invalid_argument("source \"" + source +
                                "\": " + (kind == "v4l2" ? "no device path" : "no camera id or address"));
  }
  if (kind == "v4l2") return std::make_unique<V4l2Camera>(where, settings);
  return std::make_unique<AravisCamera>(where, settings);
}

}  // namespace ccdlane
