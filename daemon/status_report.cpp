// Strings are assigned within the capacity reserved at construction, so a status second
// never allocates (std::string::assign keeps its buffer when the text fits).
#include "daemon/status_report.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "bus/lcm_publisher.hpp"

namespace ccdlane {
namespace {

static_assert(static_cast<int>(CameraState::starting) == status_t::CAMERA_STARTING);
static_assert(static_cast<int>(CameraState::streaming) == status_t::CAMERA_STREAMING);
static_assert(static_cast<int>(CameraState::stalled) == status_t::CAMERA_STALLED);
static_assert(static_cast<int>(CameraState::recovering) == status_t::CAMERA_RECOVERING);
static_assert(static_cast<int>(CameraState::ended) == status_t::CAMERA_ENDED);
static_assert(static_cast<int>(GyroState::none) == status_t::GYRO_NONE);
static_assert(static_cast<int>(GyroState::starting) == status_t::GYRO_STARTING);
static_assert(static_cast<int>(GyroState::ok) == status_t::GYRO_OK);
static_assert(static_cast<int>(GyroState::stale) == status_t::GYRO_STALE);
static_assert(static_cast<int>(GyroState::lost) == status_t::GYRO_LOST);
using calibration::OnlineMountState;
static_assert(static_cast<int>(OnlineMountState::off) == status_t::CALIBRATION_OFF);
static_assert(static_cast<int>(OnlineMountState::uncalibrated) == status_t::CALIBRATION_UNCALIBRATED);
static_assert(static_cast<int>(OnlineMountState::calibrating) == status_t::CALIBRATION_CALIBRATING);
static_assert(static_cast<int>(OnlineMountState::calibrated) == status_t::CALIBRATION_CALIBRATED);
static_assert(static_cast<int>(OnlineMountState::out_of_range) == status_t::CALIBRATION_OUT_OF_RANGE);
static_assert(sizeof(status_t::not_ok_by_reason) / sizeof(std::int64_t) == kEstimateFailureKinds);

void assign_cut(std::string& field, const char* text) { field.assign(text, strnlen(text, kStatusTextMax)); }

std::int32_t period_count(std::uint64_t now, std::uint64_t before) {
  const std::uint64_t d = now >= before ? now - before : 0;
  return d > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max())
             ? std::numeric_limits<std::int32_t>::max()
             : static_cast<std::int32_t>(d);
}

std::int64_t total(std::uint64_t v) { return static_cast<std::int64_t>(v); }

}  // namespace

StatusReport::StatusReport(const std::string& camera, const std::string& instance) {
  message_.instance.reserve(kStatusTextMax);
  assign_cut(message_.instance, instance.c_str());
  message_.camera.reserve(kStatusTextMax);
  message_.camera_problem.reserve(kStatusTextMax);
  message_.gyro_problem.reserve(kStatusTextMax);
  assign_cut(message_.camera, camera.c_str());
}

const status_t& StatusReport::update(const StatusInputs& in) {
  const PipelineTotals& t = in.totals;
  status_t& m = message_;
  m.utime = in.utime;
  m.uptime_us = in.uptime_us;
  m.period_us = in.uptime_us - previous_uptime_us_;
  m.ready = t.ready ? 1 : 0;

  m.frames_in = period_count(t.frames_in, previous_.frames_in);
  m.frames_processed = period_count(t.frames_processed, previous_.frames_processed);
  m.frames_dropped = period_count(t.frames_dropped, previous_.frames_dropped);
  m.frames_ok = period_count(t.frames_ok, previous_.frames_ok);
  m.ok_rate = m.frames_processed > 0 ? static_cast<double>(m.frames_ok) / m.frames_processed
                                     : std::numeric_limits<double>::quiet_NaN();

  m.latency_samples = static_cast<std::int32_t>(std::min<std::int64_t>(in.latency.samples, 0x7fffffff));
  m.latency_p50_us = in.latency.p50_us;
  m.latency_p99_us = in.latency.p99_us;
  m.latency_max_us = in.latency.max_us;

  m.camera_state = static_cast<std::int8_t>(t.camera);
  assign_cut(m.camera_problem, in.camera_problem);
  m.gyro_state = static_cast<std::int8_t>(in.gyro);
  assign_cut(m.gyro_problem, in.gyro_problem);
  m.allocations_since_ready = total(in.allocations_since_ready);

  m.frames_in_total = total(t.frames_in);
  m.frames_processed_total = total(t.frames_processed);
  m.frames_dropped_total = total(t.frames_dropped);
  std::uint64_t not_ok = 0;
  for (int i = 0; i < kEstimateFailureKinds; ++i) {
    m.not_ok_by_reason[i] = total(t.not_ok_by_reason[static_cast<std::size_t>(i)]);
    not_ok += t.not_ok_by_reason[static_cast<std::size_t>(i)];
  }
  m.frames_not_ok_total = total(not_ok);
  m.source_dropped_total = total(t.source.dropped);
  m.source_errors_total = total(t.source.errors);
  m.source_timeouts_total = total(t.source.timeouts);
  m.source_reconnects_total = total(t.source.reconnects);
  m.gyro_samples_total = total(in.gyro_counters.samples);
  m.gyro_errors_total = total(in.gyro_counters.errors);
  m.gyro_timeouts_total = total(in.gyro_counters.timeouts);
  m.gyro_reconnects_total = total(in.gyro_counters.reconnects);
  m.no_attitude_total = total(t.no_attitude);
  m.gyro_refused_total = total(in.gyro_counters.refused);
  m.vehicle_state = static_cast<std::int8_t>(in.vehicle.state);
  m.vehicle_states_total = total(in.vehicle.taken);
  for (std::size_t i = 0; i < in.vehicle.refused.size(); ++i)
    m.vehicle_refused_by_cause[i] = total(in.vehicle.refused[i]);
  m.publish_errors_total = total(t.publish_errors);
  m.frame_publish_errors_total = total(t.frame_publish_errors);
  m.latency_samples_lost_total = total(t.latency_samples_lost);

  const calibration::OnlineMountStatus& k = in.calibration;
  m.calibration_state = static_cast<std::int8_t>(k.state);
  m.calibration_progress = k.progress;
  m.calibration_yaw_deg = k.applied.psi_deg;
  m.calibration_pitch_deg = k.applied.theta_deg;
  m.calibration_yaw_estimate_deg = k.estimate.psi_deg;
  m.calibration_pitch_estimate_deg = k.estimate.theta_deg;
  m.calibration_yaw_sigma_deg = k.sigma.psi_deg;
  m.calibration_pitch_sigma_deg = k.sigma.theta_deg;
  m.calibration_frames_total = k.frames;

  previous_ = t;
  previous_uptime_us_ = in.uptime_us;
  return m;
}

void StatusReport::summary_line(char* out, std::size_t size) const {
  const status_t& m = message_;
  const double seconds = m.period_us > 0 ? static_cast<double>(m.period_us) * 1e-6 : 1.0;
  const char* camera = to_string(static_cast<CameraState>(m.camera_state));
  const char* gyro = to_string(static_cast<GyroState>(m.gyro_state));
  // A gyro that keeps hanging up is worth a glance in `systemctl status`; one that never
  // did needs no words.
  char reconnects[40] = "";
  if (m.gyro_reconnects_total > 0)
    std::snprintf(reconnects, sizeof reconnects, " (%lld reconnects)", static_cast<long long>(m.gyro_reconnects_total));
  // A broken vehicle gateway silences LDW: say so where a mechanic looks first.
  const char* vehicle = m.vehicle_state == status_t::VEHICLE_FAULT ? ", vehicle fault" : "";
  std::snprintf(out, size, "%s %.1f fps, %.0f%% ok, %lld dropped, p99 %.1f ms, gyro %s%s%s, %lld allocations%s%s",
                camera, m.frames_processed / seconds, std::isnan(m.ok_rate) ? 0.0 : 100.0 * m.ok_rate,
                static_cast<long long>(m.frames_dropped_total), static_cast<double>(m.latency_p99_us) * 1e-3, gyro,
                reconnects, vehicle, static_cast<long long>(m.allocations_since_ready),
                m.camera_problem.empty() ? "" : "; camera: ", m.camera_problem.c_str());
}

}  // namespace ccdlane
