// The 3DM-GX1 as the daemon's AttitudeProvider: a Gx1Session on a serial device, or on
// the slave side of an in-process Gx1Emulator ("emulated"), read by the gyro thread.
#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "daemon/attitude_provider.hpp"
#include "drivers/gx1/gx1_emulator.hpp"
#include "drivers/gx1/gx1_session.hpp"

namespace ccdlane {

class Gx1AttitudeProvider final : public AttitudeProvider {
 public:
  // A sensor on `device` (a serial device path).
  explicit Gx1AttitudeProvider(std::string device, gx1::SessionOptions options = {});
  // The emulator on a pty, reporting `script`'s attitude; the session reads its slave.
  Gx1AttitudeProvider(gx1::EmulatorOptions emulator, gx1::SessionOptions options = {});
  ~Gx1AttitudeProvider() override;

  std::string open() override;
  void run(const std::atomic<bool>& stop) override;
  void close() override;
  std::optional<Gx1Angles> attitude_at(std::int64_t t_ns) const override;
  GyroState state() const override;
  void last_problem(char* out, std::size_t size) const override;
  GyroCounters counters() const override;
  std::string describe() const override;

  // The emulator, when emulated (for fault injection in tests); else null.
  gx1::Gx1Emulator* emulator() { return emulator_.get(); }

 private:
  void note(const char* line);  // the session's log lines: logged, and kept as the problem

  std::string device_;
  gx1::SessionOptions options_;
  std::unique_ptr<gx1::Gx1Emulator> emulator_;
  std::unique_ptr<gx1::Gx1Session> session_;
  std::atomic<bool> opened_{false};
  mutable std::mutex problem_mutex_;  // taken when the session logs (events, not samples)
  char problem_[256] = {};
};

}  // namespace ccdlane
