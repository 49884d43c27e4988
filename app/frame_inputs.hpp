// One frame's inputs to the lane estimator (core/lane/frame_inputs.hpp), built by the one
// function the daemon, `ccdlane replay` and `ccdlane calibrate mount` all call: the same
// frame gives the estimator the same inputs wherever it is played.
#pragma once

#include <cstdint>
#include <optional>

#include "base/gx1_angles.hpp"
#include "base/image_view.hpp"
#include "bus/frame_message.hpp"
#include "core/lane/frame_inputs.hpp"
#include "drivers/frame_source.hpp"
#include "drivers/frames/frames_csv.hpp"

namespace ccdlane {

// What the running machine knows at the frame beside what the frame carries: empty in a
// tool replaying a recording.
struct LiveReadings {
  std::optional<Gx1Angles> gyro;         // the live gyro at the frame's time (used when the frame has none)
  std::optional<double> yaw_rate_radps;  // the live gyro's turn rate at it
  std::optional<VehicleInputs> vehicle;  // the bus's vehicle state, when fresh
  bool gyro_delivering = true;           // the live gyro is not stale or lost
};

// `image` null: the frame could not be read. `meta`: what the frame carries (its
// timestamps, a recorded gyro reading and vehicle values); `frame`: the run's count.
// The rules, as the daemon has them:
//  * the attitude is the frame's own reading, else the live gyro's;
//  * the vehicle is the recording's when the frame has recorded values (a recording plays
//    with the vehicle it was made with), else the bus's, else none ([vehicle] speed_kmh);
//  * a readable frame with no turn rate of its own takes the live gyro's, unless it is a
//    recording's frame (whose vehicle this gyro did not turn);
//  * camera_ok is whether the frame could be read; a configured gyro that gave a readable
//    frame no reading is at fault for it, and for an unreadable one the live gyro's
//    state says.
// What a recorded frame carries, as a source playing it would deliver it: a row of a
// frame directory's frames.csv, or a logged frame_t.
FrameMeta recorded_frame_meta(const FrameRow& row);
FrameMeta recorded_frame_meta(const FrameRecord& record);

FrameInputs frame_inputs(const ImageView* image, std::uint64_t frame, const FrameMeta& meta, const LiveReadings& live,
                         bool gyro_configured);

}  // namespace ccdlane
