// A synthetic drive: for each frame, where the car is on a multi-lane road and how the
// camera is turned (weaving in the lane, pitching over bumps, swaying, changing lanes),
// i.e. the truth a rendered frame shows, and the gyro reading it would come with.
#pragma once

#include <array>
#include <cstdint>

#include "base/gx1_angles.hpp"
#include "core/geometry/attitude.hpp"
#include "core/geometry/camera_model.hpp"
#include "core/synth/synth_config.hpp"

namespace ccdlane {

constexpr int kMaxRoadLines = 5;  // 4 lanes

// Everything true about one frame. The road frame is the fixed frame of docs/geometry.md
// aligned with the lane (x along it, origin on the road below the camera), so the lane
// lines are y = y0_j + c x^2 (m = 0) and the vehicle's heading shows in the camera yaw.
struct SynthFrame {
  std::uint64_t index = 0;
  std::int64_t t_ns = 0;
  CameraPose pose;                            // the camera in the road frame
  double odometer_mm = 0.0;                   // distance driven: where the dashes are
  int num_lines = 0;                          // lines of the road, left to right
  std::array<double, kMaxRoadLines> y0_mm{};  // left to right (largest first)
  double c_per_mm = 0.0;
  int ego_lane = 0;                // the lane the vehicle is in, 0 = leftmost
  double lateral_offset_mm = 0.0;  // from the ego lane's centre, positive left
  double heading_deg = 0.0;        // vehicle relative to the lane, positive left
  double lane_width_mm = 0.0;
  Gx1Angles gyro;  // the true attitude as the 3DM-GX1 reports it, plus noise
};

class SynthDrive {
 public:
  // `scene` gives the road and the motion; `mount` is the camera's nominal pose on the
  // vehicle (its attitude, height and focal length), on which the motion is added.
  // With loop_s > 0 the drive is made to repeat every loop_s seconds without a seam, for
  // a source that renders loop_s of it and plays that for ever: each periodic motion
  // (weave, bumps and their overtones, sway) gets a whole number of cycles in loop_s, at
  // least one (its amplitude scaled down where its period is shortened, so that it turns
  // no harder than configured), and the speed a whole number of dash cycles (dash and
  // gap), the nearest to what `scene` asks. Frame loop_s x rate_hz then shows what frame 0 shows, and the step
  // across the seam is an ordinary one: the lane filter and a gyro's yaw rate see no
  // jump. A lane change, and scenery with periods of its own (crossings, road markings,
  // shadows, texture), are not made periodic.
  SynthDrive(const SynthConfig& scene, const CameraPose& mount, double loop_s = 0.0);

  // The truth of frame k (pure: any k, any order, same answer for the same seed).
  SynthFrame frame(std::uint64_t k) const;
  // frame(k).t_ns alone: k / [synth] rate_hz, in ns (cheap, no allocation).
  std::int64_t t_ns(std::uint64_t k) const;

  // Where road line j (0 = leftmost) lies laterally, relative to the road's centre.
  double line_position_mm(int j) const;
  int num_lines() const { return synth_.lanes + 1; }

 private:
  double vehicle_position_mm(double t_s) const;  // lateral, relative to the road centre, + left

  SynthConfig synth_;  // with loop_s, its speed and periods those of the loop
  AttitudeDeg mount_;
  double H_mm_, f_mm_;
  double bump_overtone_[2] = {2.7, 6.1};  // of the bump frequency: incommensurate unless looping
  double bump_phase_[3];
  double roll_phase_, weave_phase_;
};

}  // namespace ccdlane
