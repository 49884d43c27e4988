// The session does the hard parts (handshake, time stamps, history, hang-up recovery);
// this maps its states and counters onto the daemon's status and logs its events.
#include "app/gx1_attitude_provider.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "base/clock.hpp"

namespace ccdlane {

Gx1AttitudeProvider::Gx1AttitudeProvider(std::string device, LogSink log, gx1::SessionOptions options)
    : device_(std::move(device)), log_(std::move(log)), options_(options) {
  options_.vehicle_attitude_only = true;  // a vehicle's gyro: a reading it cannot have is a fault
}

Gx1AttitudeProvider::Gx1AttitudeProvider(gx1::EmulatorOptions emulator, LogSink log, gx1::SessionOptions options)
    : device_("emulated"),
      log_(std::move(log)),
      options_(options),
      emulator_(std::make_unique<gx1::Gx1Emulator>(std::move(emulator), log_)) {
  options_.vehicle_attitude_only = true;
}

Gx1AttitudeProvider::~Gx1AttitudeProvider() { close(); }

void Gx1AttitudeProvider::note(LogLevel level, const char* category, const char* line) {
  // While an absent device is retried, each failed attempt only updates the problem: the
  // absence was said once, and the line that finds the device says the rest.
  if (!retrying_.load(std::memory_order_relaxed)) log_to(log_, level, category, "%s", line);
  std::lock_guard<std::mutex> lock(problem_mutex_);
  std::snprintf(problem_, sizeof problem_, "%s", line);
}

std::string Gx1AttitudeProvider::open() {
  std::string path = device_;
  if (emulator_) {
    if (const int rc = emulator_->start(); rc < 0)
      return "gyro.device: \"emulated\": cannot start the 3DM-GX1 emulator: " + std::string(std::strerror(-rc));
    path = emulator_->slave_path();
  }
  session_ = std::make_unique<gx1::Gx1Session>(
      path, options_, [this](LogLevel level, const char* category, const char* line) { note(level, category, line); });
  session_->set_cancelled(open_cancelled_);
  if (const int rc = session_->open(); rc < 0) {
    const std::string why = rc == -ECANCELED   ? "start-up interrupted"
                            : rc == -ETIMEDOUT ? "the sensor did not answer"
                                               : gx1::serial_open_error(rc);
    const std::string line = "gyro.device: \"" + device_ + "\": " + path + ": " + why;
    // Not a device at all (a file named by mistake): a configuration error, not an
    // absence to wait out, and the start fails.
    if (emulator_ || rc == gx1::SerialPort::kNotACharacterDevice) {
      session_.reset();
      if (emulator_) emulator_->stop();
      return line;
    }
    // Kept: run() retries the device, and until it answers the gyro is reported lost.
    absent_.store(true, std::memory_order_release);
    std::lock_guard<std::mutex> lock(problem_mutex_);
    std::snprintf(problem_, sizeof problem_, "absent: %s", line.c_str());
    return line;
  }
  {
    std::lock_guard<std::mutex> lock(problem_mutex_);
    problem_[0] = '\0';  // the handshake's lines are not problems
  }
  opened_.store(true, std::memory_order_release);
  return "";
}

void Gx1AttitudeProvider::run(const std::atomic<bool>& stop) {
  if (!session_) return;
  // A reconfiguration (a retry, a recovery) waits for the sensor in steps: a stop
  // request abandons it instead of waiting out the handshake's seconds.
  session_->set_cancelled([&stop] { return stop.load(std::memory_order_acquire); });
  if (absent_.load(std::memory_order_acquire)) retry_until_found(stop);
  while (!stop.load(std::memory_order_acquire)) session_->poll_once(100);
}

void Gx1AttitudeProvider::retry_until_found(const std::atomic<bool>& stop) {
  constexpr std::int64_t kFirstBackoffNs = 500'000'000, kMaxBackoffNs = 8'000'000'000;
  std::int64_t backoff = kFirstBackoffNs;
  retrying_.store(true, std::memory_order_relaxed);
  while (!stop.load(std::memory_order_acquire)) {
    // Sleep in short steps: stopping must not wait out a backoff.
    for (const std::int64_t until = monotonic_ns() + backoff; monotonic_ns() < until;) {
      if (stop.load(std::memory_order_acquire)) break;
      sleep_until(std::min(until, monotonic_ns() + 100'000'000));
    }
    if (stop.load(std::memory_order_acquire)) break;
    if (session_->open() == 0) {
      retrying_.store(false, std::memory_order_relaxed);
      {
        std::lock_guard<std::mutex> lock(problem_mutex_);
        problem_[0] = '\0';
      }
      opened_.store(true, std::memory_order_release);
      absent_.store(false, std::memory_order_release);
      log_to(log_, LogLevel::notice, "gyro", "%s: found after being absent at start: streaming", device_.c_str());
      return;
    }
    {
      std::lock_guard<std::mutex> lock(problem_mutex_);
      if (std::strncmp(problem_, "absent: ", 8) != 0) {
        char why[sizeof problem_];
        std::snprintf(why, sizeof why, "%s", problem_);
        std::snprintf(problem_, sizeof problem_, "absent: %.240s", why);
      }
    }
    backoff = std::min(2 * backoff, kMaxBackoffNs);
  }
  retrying_.store(false, std::memory_order_relaxed);
}

void Gx1AttitudeProvider::close() {
  if (session_) session_->close();
  if (emulator_) emulator_->stop();
}

std::optional<Gx1Angles> Gx1AttitudeProvider::attitude_at(std::int64_t t_ns) const {
  if (!session_) return std::nullopt;
  const gx1::AttitudeQuery q = session_->attitude_at(t_ns);
  if (q.status != gx1::AttitudeStatus::ok) return std::nullopt;
  return q.angles;
}

std::optional<double> Gx1AttitudeProvider::yaw_rate_at(std::int64_t t_ns) const {
  if (!session_) return std::nullopt;
  const gx1::AttitudeQuery q = session_->attitude_at(t_ns);
  if (q.status != gx1::AttitudeStatus::ok || !q.has_rate) return std::nullopt;
  // The sensor's yaw turns about its Earth frame's down axis (docs/gx1.md section 8): the
  // vehicle's yaw rate about up is its negative, whatever the camera's mounting yaw.
  return -gx1::yaw_angle_rate_radps(q.angles, q.rate_radps);
}

std::optional<std::int64_t> Gx1AttitudeProvider::newest_sample_ns() const {
  if (!session_) return std::nullopt;
  const std::uint64_t n = session_->history().count();
  gx1::Gx1Sample newest;
  if (n == 0 || !session_->history().sample(n - 1, newest)) return std::nullopt;
  return newest.t_ns;
}

GyroState Gx1AttitudeProvider::state() const {
  if (absent_.load(std::memory_order_acquire)) return GyroState::lost;
  if (!opened_.load(std::memory_order_acquire) || !session_) return GyroState::starting;
  switch (session_->state()) {
    case DeviceState::opening:
    case DeviceState::configuring: return GyroState::starting;
    case DeviceState::recovering:
    case DeviceState::closed: return GyroState::lost;
    case DeviceState::streaming: break;
  }
  // Streaming, but is it still talking? The same age limit as the priors use.
  const gx1::AttitudeQuery q = session_->attitude_at(monotonic_ns());
  return q.status == gx1::AttitudeStatus::ok ? GyroState::ok : GyroState::stale;
}

void Gx1AttitudeProvider::last_problem(char* out, std::size_t size) const {
  if (size == 0) return;
  if (state() == GyroState::ok) {
    out[0] = '\0';
    return;
  }
  std::lock_guard<std::mutex> lock(problem_mutex_);
  std::snprintf(out, size, "%s", problem_);
}

GyroCounters Gx1AttitudeProvider::counters() const {
  GyroCounters c;
  if (!session_) return c;
  const gx1::SessionCounters s = session_->counters();
  c.samples = s.samples;
  c.errors = s.bad_checksums + s.unconfirmed + s.hangups;
  c.timeouts = s.stream_timeouts + s.poll_timeouts;
  c.reconnects = s.reopens;
  c.refused = s.refused;
  return c;
}

std::string Gx1AttitudeProvider::describe() const {
  std::string d = "3dm-gx1:" + (emulator_ ? "emulated (" + emulator_->slave_path() + ")" : device_);
  return d + (options_.continuous ? ", continuous" : ", polled");
}

}  // namespace ccdlane
