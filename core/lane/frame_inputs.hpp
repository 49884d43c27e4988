// Everything one frame brings to the lane estimator: its pixels, time and numbers, the
// gyro's attitude at it and where that came from, and the vehicle's state. Built once per
// frame by app/frame_inputs.hpp's frame_inputs(), which the daemon, replay and calibrate
// all call, so that they hand the estimator the same inputs for the same frame.
#pragma once

#include <cstdint>
#include <optional>

#include "base/gx1_angles.hpp"
#include "base/image_view.hpp"
#include "core/ldw/ldw_warning.hpp"

namespace ccdlane {

// What the vehicle tells about this frame (a CAN gateway's vehicle_state_t, or replay's
// frames.csv columns), and the health the caller knows of.
struct VehicleInputs {
  std::optional<double> speed_mps;       // empty: [vehicle] speed_kmh
  std::optional<double> yaw_rate_radps;  // + turning left; empty: none measured
  ldw::TurnIndicator indicator = ldw::TurnIndicator::none;
  bool camera_ok = true;   // false: the camera stalled or failed (LDW "camera_fault")
  bool gyro_ok = true;     // false: a configured gyro is not delivering ("gyro_fault")
  bool vehicle_ok = true;  // false: the gateway sends only refused states or stopped ("vehicle_fault")
  // false: the caller knows the mount is not to be trusted (LDW "not_calibrated"); the
  // estimator's own online refinement says so too when the mount it learned is out of range.
  bool calibrated = true;
};

// Where a frame's gyro attitude came from.
enum class AttitudeSource : std::uint8_t {
  none,      // no reading for this frame
  recorded,  // the frame's own (a frame directory's columns, a logged frame_t, the synthetic drive)
  live,      // the running gyro's, interpolated at the frame's time
};

struct FrameInputs {
  std::uint64_t frame = 0;         // the run's own count, unique within a run
  std::uint64_t source_frame = 0;  // the source's id for it (may wrap or restart)
  std::int64_t t_ns = 0;           // the frame's timestamp (as recorded, for a recording)
  // The pixels, camera Nu x Nv; empty when the frame could not be read (ok = false,
  // no_frame: the lane departure warning coasts).
  std::optional<ImageView> image;
  std::optional<Gx1Angles> gyro;  // the 3DM-GX1 reading at t_ns
  AttitudeSource attitude_source = AttitudeSource::none;
  VehicleInputs vehicle;
};

}  // namespace ccdlane
