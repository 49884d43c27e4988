// A raw frame as an LCM message (ccdlane.frame_t, lcmtypes/ccdlane/frame_t.lcm) and back:
// what ccdlaned publishes for lcm-logger, `ccdlane record` logs and replay reads.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <ccdlane/frame_t.hpp>

#include "base/gx1_angles.hpp"
#include "base/image_view.hpp"
#include "base/turn_indicator.hpp"

namespace ccdlane {

// What a recorded frame carries besides its pixels.
struct FrameRecord {
  std::uint64_t sequence = 0;         // the source's frame number (frames.csv row for a frame directory)
  std::int64_t t_ns = 0;              // the frame's own timestamp
  std::int64_t utime = 0;             // wall-clock capture time, microseconds since the Unix epoch
  std::optional<Gx1Angles> gyro;      // the gyro reading at t_ns, if there is one
  std::uint64_t source_sequence = 0;  // the source's own id for the frame (may wrap or restart)
  // The vehicle at the frame, if known (vehicle_state_t; frames.csv's columns).
  std::optional<double> speed_kmh = std::nullopt;
  std::optional<double> yaw_rate_radps = std::nullopt;  // + turning left
  TurnIndicator indicator = TurnIndicator::none;
};

// Sizes msg.data for width x height frames of `format` (rows packed: row_stride = width x
// bytes per pixel). The one allocation; to_frame_message() then allocates nothing.
void prepare_frame_message(frame_t& msg, int width, int height, PixelFormat format);

// Copies `image` and `record` into msg, prepared for the image's size and format. False
// (msg unchanged) when it was prepared for another size or format.
bool to_frame_message(const ImageView& image, const FrameRecord& record, frame_t& msg);

// The image a decoded message holds: a view into msg.data, valid while msg lives. Returns
// "" or why the message holds no usable image ("frame 12: data_size 100 is not
// row_stride x height = 480000").
std::string frame_image(const frame_t& msg, ImageView& image);

FrameRecord frame_record(const frame_t& msg);

}  // namespace ccdlane
