// What a camera driver is asked for: size, format, rate, exposure, gain, buffering and the
// recovery timings. One struct for V4L2 and Aravis, so the daemon configures both alike.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/image_view.hpp"

namespace ccdlane {

// Whether 8-bit capture keeps the colour a camera offers.
enum class ColourCapture : std::uint8_t {
  grey,       // mono8: a mono format, or the Y plane of YUYV/UYVY; nothing else
  automatic,  // rgb8 when the device offers a colour format, else mono8
  colour,     // rgb8, or refuse a device that offers no colour format
};

struct CameraSettings {
  int width = 800;  // the reference DH-HV2003UC's sensor
  int height = 600;
  PixelFormat format = PixelFormat::mono8;  // mono16: deep mono, `colour` is ignored
  ColourCapture colour = ColourCapture::grey;
  // The device's own name of the pixel format to use ("BayerRG8"), if it must be that one
  // among those `format`/`colour` allow; empty: the driver's preference. Aravis only.
  std::string device_format;
  double fps = 30.0;  // 0: leave the device's own rate
  std::optional<double> exposure_us;
  std::optional<double> gain;  // device units (dB on GenICam cameras)
  // Further controls by the device's own name (V4L2 control name, GenICam feature name).
  std::vector<std::pair<std::string, std::string>> controls;
  int buffer_count = 6;      // driver-side buffers queued to the device
  int stall_timeout_ms = 0;  // no frame for this long -> restart; 0: max(1 s, 10 periods)
  int reopen_min_ms = 100;   // backoff between reopen attempts: doubles up to the max
  int reopen_max_ms = 2000;
  int packet_size = 0;  // GigE Vision packet size in bytes; 0: negotiate

  int effective_stall_timeout_ms() const {
    if (stall_timeout_ms > 0) return stall_timeout_ms;
    const int ten_periods = fps > 0 ? static_cast<int>(10000.0 / fps) : 0;
    return ten_periods > 1000 ? ten_periods : 1000;
  }
};

}  // namespace ccdlane
