// The vehicle drive's geometry: the road's centre line is integrated step by step
// (straights, arcs, clothoids), the camera follows a prescribed Frenet offset at the set
// speed, the vehicle points where the camera moves, and the wheels are projected onto
// the road by Newton's method. Derivatives (heading, yaw rate) are central differences
// of exact positions.
#include "core/synth/vehicle_drive.hpp"

#include <algorithm>
#include <cmath>

#include "core/synth/random.hpp"

namespace ccdlane {
namespace {

constexpr double kTwoPi = 2.0 * kPi;

double wrap_angle(double a) { return std::remainder(a, kTwoPi); }

}  // namespace

VehicleDrive::VehicleDrive(const VehicleScenario& scenario, const ldw::VehicleConfig& vehicle)
    : scenario_(scenario), vehicle_(vehicle) {
  if (scenario_.road.empty()) scenario_.road.push_back({});
  double s = 0.0;
  for (const RoadSegment& seg : scenario_.road) {
    segment_s_.push_back(s);
    s += seg.length_m;
  }
  const double length = scenario_.speed_kmh / 3.6 * scenario_.duration_s + 1000.0;
  knots_.reserve(static_cast<std::size_t>(length / kRoadStepM) + 2);
  knots_.push_back({});
  for (double u = 0.0; u < length; u += kRoadStepM) knots_.push_back(advance(knots_.back(), u, kRoadStepM));
  const std::uint64_t seed = scenario_.seed;
  weave_phase_ = {kTwoPi * synth::unit(synth::hash(seed, 31, 0)), kTwoPi * synth::unit(synth::hash(seed, 31, 1))};
  bump_phase_ = kTwoPi * synth::unit(synth::hash(seed, 32));
  roll_phase_ = kTwoPi * synth::unit(synth::hash(seed, 33));
}

VehicleDrive::Pose2 VehicleDrive::advance(const Pose2& p, double s, double u) const {
  // Within a step the curvature is linear (the pieces start and end on whole steps), so
  // the heading is a quadratic in the distance, exactly; the position is its direction
  // integrated by 5-point Gauss-Legendre, exact to ~1e-15 m over a step, and smooth
  // across steps (the drive differentiates it).
  static constexpr double node[] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640,
                                    0.9061798459386640};
  static constexpr double weight[] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                                      0.2369268850561891};
  const double k0 = curvature_at(s), k1 = curvature_at(s + u);
  const double rate = u != 0.0 ? (k1 - k0) / u : 0.0;
  auto heading = [&](double tau) { return p.heading + k0 * tau + 0.5 * rate * tau * tau; };
  double x = p.x, y = p.y;
  for (int i = 0; i < 5; ++i) {
    const double tau = 0.5 * u * (1.0 + node[i]);
    x += 0.5 * u * weight[i] * std::cos(heading(tau));
    y += 0.5 * u * weight[i] * std::sin(heading(tau));
  }
  return {x, y, heading(u)};
}

std::uint64_t VehicleDrive::num_frames() const {
  return static_cast<std::uint64_t>(std::floor(scenario_.duration_s * scenario_.rate_hz)) + 1;
}

VehicleDrive::Pose2 VehicleDrive::road_at(double s) const {
  const double clamped = std::clamp(s, 0.0, kRoadStepM * static_cast<double>(knots_.size() - 1));
  const auto i = std::min(static_cast<std::size_t>(clamped / kRoadStepM), knots_.size() - 1);
  const double s0 = kRoadStepM * static_cast<double>(i);
  return advance(knots_[i], s0, s - s0);
}

double VehicleDrive::curvature_at(double s) const {
  const auto i = static_cast<std::size_t>(
      std::max<std::ptrdiff_t>(0, std::upper_bound(segment_s_.begin(), segment_s_.end(), s) - segment_s_.begin() - 1));
  const RoadSegment& seg = scenario_.road[i];
  const double before = i > 0 ? scenario_.road[i - 1].curvature_per_m : seg.curvature_per_m;
  const double u = s - segment_s_[i];
  if (seg.transition_m <= 0.0 || u >= seg.transition_m) return seg.curvature_per_m;
  return before + (seg.curvature_per_m - before) * std::max(0.0, u) / seg.transition_m;
}

double VehicleDrive::camera_offset_from_road_centre(double t) const {
  const VehicleScenario& sc = scenario_;
  double n = 0.5 * (line_position_m(sc.ego_lane) + line_position_m(sc.ego_lane + 1)) + sc.start_offset_m;
  if (sc.drift_at_s >= 0.0 && t > sc.drift_at_s) {
    // Lateral velocity rising as (1 - cos) over the ramp, then constant.
    const double T = sc.drift_ramp_s, tau = t - sc.drift_at_s;
    n +=
        tau < T ? 0.5 * sc.drift_mps * (tau - T / kPi * std::sin(kPi * tau / T)) : sc.drift_mps * (0.5 * T + (tau - T));
  }
  for (std::size_t i = 0; i < 2; ++i)
    n += sc.weave_m[i] * std::sin(kTwoPi * t / sc.weave_period_s[i] + weave_phase_[i]);
  for (const LaneChangeManoeuvre& lc : sc.lane_changes) {
    const double u = std::clamp((t - lc.start_s) / lc.duration_s, 0.0, 1.0);
    n += lc.direction * sc.lane_width_m * 0.5 * (1.0 - std::cos(kPi * u));
  }
  return n;
}

VehicleDrive::Pose2 VehicleDrive::camera_at(double t) const {
  // The camera's Frenet position (s = v t, n prescribed) in the plane; its heading is the
  // direction of its motion.
  auto position = [this](double tt) {
    const double s = scenario_.speed_kmh / 3.6 * tt;
    const Pose2 r = road_at(s);
    const double n = camera_offset_from_road_centre(tt);
    return Pose2{r.x - n * std::sin(r.heading), r.y + n * std::cos(r.heading), 0.0};
  };
  const double h = 1e-4;
  const Pose2 a = position(t - h), b = position(t + h), p = position(t);
  return {p.x, p.y, std::atan2(b.y - a.y, b.x - a.x)};
}

double VehicleDrive::lateral_of(double x, double y, double s_hint) const {
  // Newton on the foot point: (P - r(s)) . tangent(s) = 0.
  double s = s_hint, n = 0.0;
  for (int it = 0; it < 8; ++it) {
    const Pose2 r = road_at(s);
    const double tx = std::cos(r.heading), ty = std::sin(r.heading);
    const double ex = x - r.x, ey = y - r.y;
    const double along = ex * tx + ey * ty;
    n = -ex * ty + ey * tx;
    s += along / (1.0 - curvature_at(s) * n);
    if (std::abs(along) < 1e-10) break;
  }
  return n;
}

VehicleFrame VehicleDrive::frame(std::uint64_t k) const {
  const VehicleScenario& sc = scenario_;
  VehicleFrame f;
  f.index = k;
  f.t_s = static_cast<double>(k) / sc.rate_hz;
  const double t = f.t_s, v = sc.speed_kmh / 3.6;
  const double s = v * t;
  f.odometer_m = s;

  const Pose2 cam = camera_at(t);
  const double h = 1e-3;
  const Pose2 before = camera_at(t - h), after = camera_at(t + h);
  f.speed_mps = std::hypot(after.x - before.x, after.y - before.y) / (2 * h);
  f.yaw_rate_radps = wrap_angle(after.heading - before.heading) / (2 * h);
  f.measured_yaw_rate_radps = f.yaw_rate_radps + sc.gyro_rate_noise_radps * synth::normal(synth::hash(sc.seed, 34, k));

  const double n = camera_offset_from_road_centre(t);
  f.ego_lane = sc.lanes - 1;
  for (int lane = 0; lane < sc.lanes; ++lane)
    if (n > line_position_m(lane + 1)) {
      f.ego_lane = lane;
      break;
    }
  const double left_line = line_position_m(f.ego_lane), right_line = line_position_m(f.ego_lane + 1);
  f.offset_m = n - 0.5 * (left_line + right_line);
  f.lateral_velocity_mps = (camera_offset_from_road_centre(t + h) - camera_offset_from_road_centre(t - h)) / (2 * h);
  f.heading_rad = wrap_angle(cam.heading - road_at(s).heading);
  f.curvature_per_m = curvature_at(s);
  f.lane_width_m = sc.lane_width_m;
  f.left_line_m = left_line - n;
  f.right_line_m = right_line - n;
  f.pitch_rad = sc.mount_pitch_rad + sc.pitch_bump_rad * std::sin(kTwoPi * t / sc.bump_period_s + bump_phase_);
  f.roll_rad = sc.mount_roll_rad + sc.roll_sway_rad * std::sin(kTwoPi * t / sc.roll_period_s + roll_phase_);

  // The front wheels' outer edges, in the plane, projected onto the road.
  const double ahead = -vehicle_.front_axle_behind_camera_mm * 1e-3;
  const double centre_left = -vehicle_.camera_left_of_centre_mm * 1e-3, half = 0.5 * vehicle_.width_mm * 1e-3;
  const double cx = std::cos(cam.heading), cy = std::sin(cam.heading);
  auto wheel_lateral = [&](double left) {
    const double x = cam.x + ahead * cx - left * cy, y = cam.y + ahead * cy + left * cx;
    return lateral_of(x, y, s + ahead);
  };
  const double half_line = 0.5 * sc.line_width_m;
  f.wheel_dlc.left_m = (left_line - half_line) - wheel_lateral(centre_left + half);
  f.wheel_dlc.right_m = wheel_lateral(centre_left - half) - (right_line + half_line);

  for (const LaneChangeManoeuvre& lc : sc.lane_changes)
    if (lc.signalled && t >= lc.start_s - lc.indicator_lead_s && t < lc.start_s + 0.8 * lc.duration_s)
      f.indicator = lc.direction > 0 ? ldw::TurnIndicator::left : ldw::TurnIndicator::right;
  return f;
}

SynthFrame VehicleDrive::synth_frame(std::uint64_t k, const CameraPose& mount, double gyro_noise_deg) const {
  const VehicleFrame v = frame(k);
  SynthFrame f;
  f.index = k;
  f.t_ns = static_cast<std::int64_t>(std::llround(v.t_s * 1e9));
  f.odometer_mm = v.odometer_m * 1000.0;
  f.num_lines = std::min(scenario_.lanes + 1, kMaxRoadLines);
  const double n = camera_offset_from_road_centre(v.t_s);
  for (int j = 0; j < f.num_lines; ++j) f.y0_mm[static_cast<std::size_t>(j)] = (line_position_m(j) - n) * 1000.0;
  f.c_per_mm = 0.5 * v.curvature_per_m * 1e-3;
  f.ego_lane = v.ego_lane;
  f.lateral_offset_mm = v.offset_m * 1000.0;
  f.heading_deg = rad_to_deg(v.heading_rad);
  f.lane_width_mm = v.lane_width_m * 1000.0;
  const double psi = mount.attitude.psi + v.heading_rad;
  f.pose.attitude = {psi, v.pitch_rad, v.roll_rad};
  f.pose.H_mm = mount.H_mm;
  f.pose.f_mm = mount.f_mm;
  const double sigma = gyro_noise_deg;
  f.gyro.roll_deg = rad_to_deg(v.roll_rad) + sigma * synth::normal(synth::hash(scenario_.seed, 21, k));
  f.gyro.pitch_deg = -rad_to_deg(v.pitch_rad) + sigma * synth::normal(synth::hash(scenario_.seed, 22, k));
  f.gyro.yaw_deg = -rad_to_deg(psi);
  return f;
}

}  // namespace ccdlane
