// The synthetic drive's motion model: smooth periodic motions with seed-dependent phases,
// a cosine-profile lane change, heading from the lateral speed.
#include "core/synth/synth_drive.hpp"

#include <algorithm>
#include <cmath>

#include "core/synth/random.hpp"

namespace ccdlane {
namespace {

// The period nearest `period` of which a whole number, at least one, fits in `loop`.
double whole_cycles_period(double period, double loop) { return loop / std::max(1.0, std::round(loop / period)); }

// A periodic motion of `amplitude` given a whole number of cycles in `loop`: its new
// period, and its amplitude scaled down where that period is shorter, by the square of
// the ratio, so that it turns no harder than configured (its acceleration, amplitude over
// period squared; its speed is then lower too). A 0.3 s loop of a 6 s weave across the
// lane at full width would swing the car sideways at 6 m/s, its heading by 13 degrees.
void loop_motion(double& period, double& amplitude, double loop) {
  const double looped = whole_cycles_period(period, loop);
  const double shorter = std::min(1.0, looped / period);
  amplitude *= shorter * shorter;
  period = looped;
}

}  // namespace

SynthDrive::SynthDrive(const SynthConfig& scene, const CameraPose& mount, double loop_s)
    : synth_(scene),
      mount_{rad_to_deg(mount.attitude.psi), rad_to_deg(mount.attitude.theta), rad_to_deg(mount.attitude.phi)},
      H_mm_(mount.H_mm),
      f_mm_(mount.f_mm) {
  const std::uint64_t s = synth_.seed;
  for (int i = 0; i < 3; ++i) bump_phase_[i] = 2 * kPi * synth::unit(synth::hash(s, 11, static_cast<std::uint64_t>(i)));
  roll_phase_ = 2 * kPi * synth::unit(synth::hash(s, 12));
  weave_phase_ = 2 * kPi * synth::unit(synth::hash(s, 13));
  if (loop_s <= 0.0) return;
  loop_motion(synth_.weave_period_s, synth_.weave_mm, loop_s);
  loop_motion(synth_.roll_period_s, synth_.roll_sway_deg, loop_s);
  loop_motion(synth_.bump_period_s, synth_.pitch_bump_deg, loop_s);
  const double bumps = loop_s / synth_.bump_period_s;
  for (double& overtone : bump_overtone_) overtone = std::max(1.0, std::round(overtone * bumps)) / bumps;
  const double dash_cycle_m = (synth_.dash_length_mm + synth_.dash_gap_mm) / 1000.0;
  if (synth_.speed_mps > 0.0 && dash_cycle_m > 0.0)  // a dash cycle's time, whole in the loop
    synth_.speed_mps = dash_cycle_m / whole_cycles_period(dash_cycle_m / synth_.speed_mps, loop_s);
}

double SynthDrive::line_position_mm(int j) const { return (0.5 * synth_.lanes - j) * synth_.lane_width_mm; }

double SynthDrive::vehicle_position_mm(double t) const {
  const double w = synth_.lane_width_mm;
  double p = 0.5 * (line_position_mm(synth_.ego_lane) + line_position_mm(synth_.ego_lane + 1));
  p += synth_.weave_mm * std::sin(2 * kPi * t / synth_.weave_period_s + weave_phase_);
  if (synth_.lane_change_at_s >= 0.0 && t > synth_.lane_change_at_s) {
    const double u = std::min(1.0, (t - synth_.lane_change_at_s) / synth_.lane_change_s);
    p -= w * 0.5 * (1.0 - std::cos(kPi * u));  // to the lane on the right
  }
  return p;
}

std::int64_t SynthDrive::t_ns(std::uint64_t k) const {
  return static_cast<std::int64_t>(std::llround(static_cast<double>(k) / synth_.rate_hz * 1e9));
}

SynthFrame SynthDrive::frame(std::uint64_t k) const {
  SynthFrame f;
  f.index = k;
  const double t = static_cast<double>(k) / synth_.rate_hz;
  f.t_ns = t_ns(k);
  f.odometer_mm = synth_.speed_mps * 1000.0 * t;

  const double p = vehicle_position_mm(t);
  f.num_lines = num_lines();
  for (int j = 0; j < f.num_lines; ++j) f.y0_mm[static_cast<std::size_t>(j)] = line_position_mm(j) - p;
  f.c_per_mm = synth_.curvature_per_mm;
  f.lane_width_mm = synth_.lane_width_mm;
  f.ego_lane = synth_.lanes - 1;
  for (int lane = 0; lane < synth_.lanes; ++lane)
    if (p > line_position_mm(lane + 1)) {
      f.ego_lane = lane;
      break;
    }
  f.lateral_offset_mm = p - 0.5 * (line_position_mm(f.ego_lane) + line_position_mm(f.ego_lane + 1));

  // Heading from the lateral speed (central difference of the position).
  const double dt = 1e-3;
  const double speed_mm_s = std::max(1.0, synth_.speed_mps * 1000.0);
  const double lateral_speed = (vehicle_position_mm(t + dt) - vehicle_position_mm(t - dt)) / (2 * dt);
  f.heading_deg = rad_to_deg(std::atan(lateral_speed / speed_mm_s));

  // Bumps: three incommensurate components so the pitch does not look periodic.
  const double b = 2 * kPi * t / synth_.bump_period_s;
  const double bump = 0.6 * std::sin(b + bump_phase_[0]) + 0.3 * std::sin(bump_overtone_[0] * b + bump_phase_[1]) +
                      0.1 * std::sin(bump_overtone_[1] * b + bump_phase_[2]);
  const double sway = std::sin(2 * kPi * t / synth_.roll_period_s + roll_phase_);
  const AttitudeDeg cam{mount_.psi_deg + f.heading_deg, mount_.theta_deg + synth_.pitch_bump_deg * bump,
                        mount_.phi_deg + synth_.roll_sway_deg * sway};
  f.pose.attitude = {deg_to_rad(cam.psi_deg), deg_to_rad(cam.theta_deg), deg_to_rad(cam.phi_deg)};
  f.pose.H_mm = H_mm_;
  f.pose.f_mm = f_mm_;

  // The 3DM-GX1 mounted with its axes on the camera's (gx1_attitude.hpp): roll = phi,
  // pitch = -theta, yaw = -psi; its roll and pitch carry the configured noise.
  const double sigma = synth_.gyro_noise_deg;
  f.gyro.roll_deg = cam.phi_deg + sigma * synth::normal(synth::hash(synth_.seed, 21, k));
  f.gyro.pitch_deg = -cam.theta_deg + sigma * synth::normal(synth::hash(synth_.seed, 22, k));
  f.gyro.yaw_deg = -cam.psi_deg;
  return f;
}

}  // namespace ccdlane
