// The lane-state Kalman filter: the vehicle's place in its lane, the lane's shape and the
// camera's pitch (and roll without a gyro), carried between frames by the vehicle's
// speed and yaw rate, updated by each frame's solve, allocation-free.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include <Eigen/Core>

namespace ccdlane::ldw {

// State (SI units, signs as in LanePose):
//   offset     d  the camera's lateral position from the lane centre, m, + left
//   heading    psi the vehicle's direction relative to the lane tangent, rad, + left
//   curvature  k  the lane's, 1/m, + bending left
//   width      w  between the lines' centres, m
//   pitch, roll   the camera's (the solve's theta and phi), rad
//   heading bias  b  what the solve's heading reads beyond the vehicle's: the camera's
//                 yaw on the vehicle less the configured mount's, rad. A mount a degree
//                 off in yaw reads as a degree of heading on every frame, and a heading
//                 taken at face value predicts a drift of speed x heading that the
//                 offsets never show (0.4-0.5 m/s on the Udacity drives). The offsets'
//                 rate tells the true heading, so the bias is observable; it persists
//                 across tracks (it is the mount's), until reset_mount().
// Motion model (a point moving at speed v along the vehicle's heading, the lane a curve
// of curvature k in Frenet coordinates):
//   d'   = v sin(psi)
//   psi' = r - v k          with the yaw rate r (+ turning left); without it psi' = 0:
//                           the driver is assumed to follow the lane, and the heading's
//                           process noise is larger to cover his steering
//   k' = w' = pitch' = roll' = b' = 0   random walks
// The camera sits ahead of the point whose velocity is along the heading (the rear
// axle); its extra lateral speed (yaw rate times that distance, a few cm/s) is left to
// the offset's process noise.
enum StateIndex : int { kOffset = 0, kHeading, kCurvature, kWidth, kPitch, kRoll, kHeadingBias, kStateSize };

using StateVector = Eigen::Matrix<double, kStateSize, 1>;
using StateMatrix = Eigen::Matrix<double, kStateSize, kStateSize>;

// Measurement components: the own lane's lines at the camera (the solve's y0 of the
// nearest line on each side, m, + left), heading (rad), curvature (1/m, 2 c of the
// solve's y = y0 + c x^2), pitch, roll (rad).
enum MeasurementIndex : int {
  kLeftLine = 0,
  kRightLine,
  kMeasuredHeading,
  kMeasuredCurvature,
  kMeasuredPitch,
  kMeasuredRoll,
  kMeasurementSize
};
using MeasurementVector = Eigen::Matrix<double, kMeasurementSize, 1>;
using MeasurementMatrix = Eigen::Matrix<double, kMeasurementSize, kMeasurementSize>;

// One frame's solve, with its covariance (the solver's, in these units). Components that
// the solve did not determine (curvature when c is fixed, roll when the gyro gives it)
// are marked absent; their rows of value and covariance are ignored.
struct LaneMeasurement {
  MeasurementVector value = MeasurementVector::Zero();
  MeasurementMatrix covariance = MeasurementMatrix::Identity();
  std::array<bool, kMeasurementSize> present{true, true, true, true, true, true};
};

struct VehicleMotion {
  double speed_mps = 0.0;
  std::optional<double> yaw_rate_radps;  // + turning left; empty: no gyro rate
};

struct LaneFilterConfig {
  double coast_s = 1.0;             // predict without an accepted measurement for at most this long
  double gate_probability = 0.999;  // Mahalanobis gate: the chi-square quantile of this probability
  int confirm_updates = 5;          // accepted updates before a new track is trusted
  // After this many measurements in a row refused by the gate, the next refused one
  // starts a new track: the road changed faster than the model allows (a curve entered
  // harder than its process noise), and coasting on the old state would drift away.
  int max_rejections = 3;
  bool track_roll = false;  // roll is a state only without the gyro (which measures it)
  // Process noise: the standard deviation each state's random walk gains in one second.
  double offset_noise_m = 0.05;
  double heading_noise_rad = 0.01;              // with a yaw rate: its error
  double heading_noise_no_yaw_rate_rad = 0.05;  // without: the driver's steering
  double curvature_noise_per_m = 5e-4;
  double width_noise_m = 0.05;
  double pitch_noise_rad = 0.03;
  double roll_noise_rad = 0.01;
  double heading_bias_noise_rad = 0.001;  // a mount's yaw shifts slowly, if at all
  // Prior sigma of the states a first measurement lacks.
  double initial_curvature_per_m = 2e-3;
  double initial_heading_rad = 0.05;
  double initial_pitch_rad = 0.05;
  double initial_roll_rad = 0.02;
  // The heading bias's: a configured mount stands when the picture shows it within 2
  // degrees in yaw (mount_refinement.hpp), so it may be that far off.
  double initial_heading_bias_rad = 0.035;

  bool operator==(const LaneFilterConfig&) const = default;
};

enum class TrackStatus : std::uint8_t {
  lost,       // no state: never initialised, or coasted longer than coast_s
  tentative,  // initialised, fewer than confirm_updates accepted measurements
  tracking,   // the last frame's measurement was accepted
  coasting,   // predicting through missed or rejected frames
};
const char* to_string(TrackStatus s);  // "lost", "tentative", "tracking", "coasting"

enum class LaneChange : std::uint8_t { none, left, right };
const char* to_string(LaneChange c);  // "none", "left", "right"

// What the filter knows after a step.
struct LaneState {
  TrackStatus status = TrackStatus::lost;
  StateVector value = StateVector::Zero();
  StateVector sigma = StateVector::Zero();  // square roots of the covariance's diagonal
  double lateral_velocity_mps = 0.0;        // v sin(psi), + toward the left
  double sigma_lateral_velocity_mps = 0.0;
  // The lateral acceleration relative to the lane, v (r - v k), + toward the left; 0
  // without a yaw rate (the model then assumes none).
  double lateral_acceleration_mps2 = 0.0;
  double since_update_s = 0.0;                // time since the last accepted measurement
  bool updated = false;                       // this step's measurement was accepted
  bool rejected = false;                      // this step had a measurement and the gate refused it
  int rejections = 0;                         // measurements refused in a row
  bool restarted = false;                     // this step's measurement started a new track after rejections
  LaneChange lane_change = LaneChange::none;  // this step re-associated to a neighbour lane
  double nis = 0.0;                           // normalised innovation squared of the accepted measurement
  int nis_dof = 0;                            //   and its degrees of freedom
};

class LaneFilter {
 public:
  explicit LaneFilter(const LaneFilterConfig& config = {});

  // Forgets the track; the heading bias learnt is kept (it is the mount's).
  void reset();
  // Forgets the track and the heading bias (another mount, another camera).
  void reset_mount();

  // Carries the state dt_s forward (dt_s >= 0) with the vehicle's motion. Marks the
  // track lost after coast_s without an accepted measurement.
  void predict(double dt_s, const VehicleMotion& motion);

  // Folds one frame's solve in. A lost track starts from it (both lines needed). A
  // measurement of the neighbour lane (the camera crossed a line: the offset jumped by
  // about one lane width) shifts the state by one width rather than averaging across
  // the line. One that fits neither, by the Mahalanobis gate, is rejected.
  void update(const LaneMeasurement& measurement);

  // predict then, when there is one, update.
  const LaneState& step(double dt_s, const VehicleMotion& motion, const LaneMeasurement* measurement);

  const LaneState& state() const { return state_; }
  const StateMatrix& covariance() const { return P_; }
  const LaneFilterConfig& config() const { return config_; }

 private:
  void initialise(const LaneMeasurement& m);
  void publish();

  LaneFilterConfig config_;
  StateVector x_ = StateVector::Zero();
  StateMatrix P_ = StateMatrix::Zero();
  std::array<double, kMeasurementSize + 1> gate_{};  // chi-square gate per measurement dimension
  double speed_mps_ = 0.0;
  std::optional<double> yaw_rate_radps_;
  int accepted_ = 0;
  // The heading bias and its variance, kept from one track to the next.
  double bias_ = 0.0, bias_variance_ = 0.0;
  LaneState state_;
};

}  // namespace ccdlane::ldw
