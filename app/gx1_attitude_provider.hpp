// The 3DM-GX1 as an AttitudeProvider: a Gx1Session on a serial device, or on the slave
// side of an in-process Gx1Emulator ("emulated"), read by a gyro thread. The daemon's
// gyro, and the one `ccdlane record` stamps frames with (library ccdlane::gyro_provider).
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "app/attitude_provider.hpp"
#include "base/log.hpp"
#include "drivers/gx1/gx1_emulator.hpp"
#include "drivers/gx1/gx1_session.hpp"

namespace ccdlane {

class Gx1AttitudeProvider final : public AttitudeProvider {
 public:
  // A sensor on `device` (a serial device path).
  Gx1AttitudeProvider(std::string device, LogSink log, gx1::SessionOptions options = {});
  // The emulator on a pty, reporting `script`'s attitude; the session reads its slave.
  Gx1AttitudeProvider(gx1::EmulatorOptions emulator, LogSink log, gx1::SessionOptions options = {});
  ~Gx1AttitudeProvider() override;

  std::string open() override;
  void run(const std::atomic<bool>& stop) override;
  void close() override;
  std::optional<Gx1Angles> attitude_at(std::int64_t t_ns) const override;
  // From the 0x31 stream's rate vector (the daemon's default stream); none from 0x0E.
  std::optional<double> yaw_rate_at(std::int64_t t_ns) const override;
  GyroState state() const override;
  void last_problem(char* out, std::size_t size) const override;
  GyroCounters counters() const override;
  std::string describe() const override;

  // CLOCK_MONOTONIC arrival time of the newest sample; nullopt before the first. For a
  // recorder that can wait for a sample after a frame rather than take the last one held.
  std::optional<std::int64_t> newest_sample_ns() const override;

  // Asked while open() waits for a sensor that does not answer: true gives up the
  // handshake, so that a stop request during start-up does not wait seconds for it.
  void set_open_cancelled(std::function<bool()> cancelled) { open_cancelled_ = std::move(cancelled); }

  // The emulator, when emulated (for fault injection in tests); else null.
  gx1::Gx1Emulator* emulator() { return emulator_.get(); }

 private:
  // The device was absent at open(): tries it again with backoff until found or stopped.
  void retry_until_found(const std::atomic<bool>& stop);
  void note(LogLevel level, const char* category,
            const char* line);  // the session's log lines: logged, and kept as the problem

  std::string device_;
  LogSink log_;
  gx1::SessionOptions options_;
  std::unique_ptr<gx1::Gx1Emulator> emulator_;
  std::unique_ptr<gx1::Gx1Session> session_;
  std::function<bool()> open_cancelled_;
  std::atomic<bool> opened_{false};
  std::atomic<bool> absent_{false};    // open() failed: the gyro thread keeps trying the device
  std::atomic<bool> retrying_{false};  // failed retries are not logged, only kept as the problem
  mutable std::mutex problem_mutex_;   // taken when the session logs (events, not samples)
  char problem_[256] = {};
};

}  // namespace ccdlane
