// A synthetic drive with a vehicle: the road (straights, arcs and clothoids),
// the vehicle's lateral motion in it (settled, drifting at a set lateral velocity,
// weaving, changing lanes with or without the indicator), and per frame the truth the
// lane departure warning is judged by: each front wheel's exact distance to its line.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/ldw/ldw_warning.hpp"
#include "core/ldw/vehicle.hpp"
#include "core/synth/synth_drive.hpp"

namespace ccdlane {

// A piece of road from where the previous one ends; the last one continues for ever.
// Its curvature reaches curvature_per_m linearly over its first transition_m (a
// clothoid, as roads are built), from the previous piece's.
struct RoadSegment {
  double length_m = 1e9;
  double curvature_per_m = 0.0;  // + bending left; |1/R|
  double transition_m = 0.0;
};

struct LaneChangeManoeuvre {
  double start_s = 0.0;
  double duration_s = 5.0;        // centre to centre, cosine profile
  int direction = 1;              // +1 to the lane on the left, -1 to the right
  bool signalled = true;          // the indicator on from indicator_lead_s before the start
  double indicator_lead_s = 1.5;  // until 80 % of the manoeuvre
};

struct VehicleScenario {
  double speed_kmh = 72.0;
  double rate_hz = 30.0;
  double duration_s = 20.0;
  // The road: lanes of equal width; lines at their centres, `line_width_m` wide.
  int lanes = 3;
  int ego_lane = 1;  // the lane at the start, 0 = leftmost
  double lane_width_m = 3.75;
  double line_width_m = 0.12;
  std::vector<RoadSegment> road;  // empty: straight
  // The camera's lateral motion (Frenet offset from its lane's centre, + left), a sum of:
  double start_offset_m = 0.0;
  double drift_at_s = -1.0;                 // the drift starts here (< 0: none),
  double drift_mps = 0.0;                   //   reaching this lateral velocity (+ left)
  double drift_ramp_s = 1.0;                //   over this long (smooth, cosine in velocity)
  std::array<double, 2> weave_m{0.0, 0.0};  // amplitudes of two sine weaves
  std::array<double, 2> weave_period_s{7.0, 2.9};
  std::vector<LaneChangeManoeuvre> lane_changes;
  // The camera's attitude: mounting plus pitching over bumps and body roll.
  double mount_pitch_rad = 0.0524;  // 3 degrees down
  double mount_roll_rad = 0.0;
  double pitch_bump_rad = 0.007;  // 0.4 degree
  double bump_period_s = 1.3;
  double roll_sway_rad = 0.005;  // 0.3 degree
  double roll_period_s = 3.5;
  double gyro_rate_noise_radps = 0.002;  // the yaw rate a gyro reports: truth plus this noise
  std::uint64_t seed = 1;
};

// The truth at one frame.
struct VehicleFrame {
  std::uint64_t index = 0;
  double t_s = 0.0;
  double speed_mps = 0.0;                // of the camera, along its path
  double yaw_rate_radps = 0.0;           // + turning left
  double measured_yaw_rate_radps = 0.0;  // as the gyro reports it
  ldw::TurnIndicator indicator = ldw::TurnIndicator::none;
  int ego_lane = 0;                   // the lane the camera is in
  double offset_m = 0.0;              // camera from the ego lane's centre, + left
  double lateral_velocity_mps = 0.0;  // d(offset)/dt
  double heading_rad = 0.0;           // vehicle relative to the lane's tangent, + left
  double curvature_per_m = 0.0;       // of the road at the camera
  double lane_width_m = 0.0;
  double left_line_m = 0.0, right_line_m = 0.0;  // the ego lane's lines from the camera, + left
  double pitch_rad = 0.0, roll_rad = 0.0;        // the camera's
  double odometer_m = 0.0;                       // along the road
  // Each front wheel's outer edge to the inner edge of the ego lane's line on its side,
  // exact (the wheel projected onto the curved line), + inside.
  ldw::SideDistances wheel_dlc;
};

class VehicleDrive {
 public:
  VehicleDrive(const VehicleScenario& scenario, const ldw::VehicleConfig& vehicle);
  // The truth at frame k (pure: any k, any order).
  VehicleFrame frame(std::uint64_t k) const;
  std::uint64_t num_frames() const;
  const VehicleScenario& scenario() const { return scenario_; }

  // The same frame as the renderer takes it (camera at `mount`'s height and focal
  // length, its yaw as the mounting; the road's lines as seen from the camera, the
  // curvature as c = k / 2), with a gyro reading whose roll and pitch carry
  // `gyro_noise_deg` of noise.
  SynthFrame synth_frame(std::uint64_t k, const CameraPose& mount, double gyro_noise_deg) const;

 private:
  struct Pose2 {
    double x = 0.0, y = 0.0, heading = 0.0;
  };
  Pose2 road_at(double s) const;  // the road's centre line
  double curvature_at(double s) const;
  double camera_offset_from_road_centre(double t) const;
  Pose2 camera_at(double t) const;                             // heading: the direction of motion
  double lateral_of(double x, double y, double s_hint) const;  // exact Frenet offset of a point
  double line_position_m(int j) const { return (0.5 * scenario_.lanes - j) * scenario_.lane_width_m; }

  VehicleScenario scenario_;
  ldw::VehicleConfig vehicle_;
  // The centre line every kRoadStepM (the curvature linear within each step).
  static constexpr double kRoadStepM = 1.0;
  Pose2 advance(const Pose2& p, double s, double u) const;
  std::vector<Pose2> knots_;
  std::vector<double> segment_s_;  // where each segment starts
  std::array<double, 2> weave_phase_{};
  double bump_phase_ = 0.0, roll_phase_ = 0.0;
};

}  // namespace ccdlane
