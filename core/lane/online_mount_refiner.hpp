// The camera mount's yaw and pitch learned while driving: per-frame solved angles on
// straight road above a speed, averaged robustly, and a correction to the configured
// mount that follows the estimate at a bounded rate and never leaves the configured
// bounds. Pure and allocation-free: the daemon feeds it one sample per frame.
//
// Why the mean is the mount: along a straight lane the vehicle's heading relative to the
// lane and its pitch over bumps average out to zero, so what the camera's solved yaw and
// pitch keep on average is how the camera sits on the vehicle (calibrate mount uses the
// same fact offline, with blocks and sigmas; openpilot learns its mount so too).
//
// In lane/ rather than calibration/, which builds on the lane estimator: the estimator's
// own mount is to be refined by it. Its names keep to namespace calibration, beside the
// mount's offline estimate.
#pragma once

#include <cstdint>
#include <optional>

namespace ccdlane::calibration {

enum class OnlineMountState : std::uint8_t {
  off,           // online refinement is not configured
  uncalibrated,  // no usable frame yet
  calibrating,   // fewer usable frames than needed (progress < 1)
  calibrated,    // the estimate is established and within the bounds
  out_of_range,  // the estimate lies beyond max_correction_deg of the configured mount
};
const char* to_string(OnlineMountState state);  // "off", "uncalibrated", ...

struct OnlineMountOptions {
  double configured_psi_deg = 0.0;            // the mount in the configuration: where refinement starts
  double configured_theta_deg = 0.0;          //   and the centre of its bounds
  double min_speed_kmh = 50.0;                // slower: towns, junctions, manoeuvres; not used
  double max_curvature_per_m = 1.0 / 500.0;   // |1/R| above which it is a bend (the solve has the curvature)
  double max_yaw_rate_deg_s = 2.0;            // turning faster (when the vehicle says): not driving along the lane
  double max_correction_deg = 6.0;            // the correction's bound, in yaw and in pitch
  double max_change_deg_per_min = 0.5;        // how fast the applied correction may move
  int frames_needed = 900;                    // usable frames before the estimate counts (30 s at 30 fps)
  // The running mean forgets with this many frames' memory, so a mount that settles
  // slowly is followed; 0 means 10 x frames_needed.
  int memory_frames = 0;
  double outlier_sigmas = 4.0;  // a frame this far from the mean (in its spread) is not used

  bool operator==(const OnlineMountOptions&) const = default;
};

// Yaw and pitch, degrees: a correction to the configured mount, or a spread.
struct MountAngles {
  double psi_deg = 0.0;
  double theta_deg = 0.0;

  bool operator==(const MountAngles&) const = default;
};

// One frame as the refiner sees it.
struct MountSample {
  std::int64_t t_ns = 0;  // the frame's time (drive time, increasing)
  bool solved = false;    // an ok solve with both lines of the own lane
  double speed_kmh = 0.0;
  double curvature_per_m = 0.0;           // the road's 1/R at the vehicle (sign ignored)
  std::optional<double> yaw_rate_deg_s;   // the vehicle's, when known
  double psi_deg = 0.0, theta_deg = 0.0;  // the camera's solved yaw and pitch
};

// Why samples were not used, since start.
struct MountSampleCounts {
  std::int64_t used = 0;
  std::int64_t unsolved = 0, slow = 0, curved = 0, turning = 0, outliers = 0;
};

// What the refiner learned, for persisting and restoring it.
struct LearnedMount {
  MountAngles estimate;  // correction the frames say, relative to the configured mount
  MountAngles applied;   // correction in use
  MountAngles spread;    // per-frame standard deviation of the solved angles
  std::int64_t frames = 0;
};

// Everything a status report says about the refinement, in one copyable value.
struct OnlineMountStatus {
  OnlineMountState state = OnlineMountState::off;
  double progress = 0.0;
  MountAngles applied, estimate, sigma;
  std::int64_t frames = 0;
};

class OnlineMountRefiner {
 public:
  explicit OnlineMountRefiner(const OnlineMountOptions& options);

  // One frame: uses it when it qualifies, then moves the applied correction toward the
  // (bounded) estimate by at most max_change_deg_per_min over the time since the last
  // sample. Returns whether the sample was used.
  bool add(const MountSample& sample);

  // Starts from a mount learned before (already validated against the bounds): the
  // state is calibrated (or out_of_range) at once and the applied correction is the
  // learned one.
  void restore(const LearnedMount& learned);
  // Forgets everything learned (state uncalibrated, correction 0).
  void reset();

  OnlineMountState state() const;
  double progress() const;       // 0..1: usable frames / frames_needed
  MountAngles estimate() const;  // the frames' correction (mean - configured)
  MountAngles sigma() const;     // of the estimate, assuming independent frames
  MountAngles spread() const;    // per frame
  const MountAngles& applied() const { return applied_; }
  const MountSampleCounts& counts() const { return counts_; }
  LearnedMount learned() const;
  OnlineMountStatus status() const;
  const OnlineMountOptions& options() const { return options_; }

 private:
  bool qualifies(const MountSample& s);
  void accumulate(double psi_deg, double theta_deg);
  void follow(std::int64_t t_ns);
  bool established() const { return frames_ >= options_.frames_needed; }

  OnlineMountOptions options_;
  int memory_ = 0;
  std::int64_t frames_ = 0;    // usable frames in the current mean
  double weight_count_ = 0.0;  // min(frames, memory): the mean's effective sample count
  MountAngles mean_;           // absolute solved angles, degrees
  double var_psi_ = 0.0, var_theta_ = 0.0;
  MountAngles applied_;
  std::optional<std::int64_t> last_t_ns_;
  MountSampleCounts counts_;
};

}  // namespace ccdlane::calibration
