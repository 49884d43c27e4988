// Where the processing thread gets the gyro's attitude at a frame's time: the 3DM-GX1
// session (a device or the in-process emulator) implements it (gx1_attitude_provider.hpp).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "base/device_states.hpp"
#include "base/gx1_angles.hpp"

namespace ccdlane {

struct GyroCounters {
  std::uint64_t samples = 0;     // readings received
  std::uint64_t errors = 0;      // bad packets, checksum errors
  std::uint64_t timeouts = 0;    // reads that saw nothing in time
  std::uint64_t reconnects = 0;  // device reopened after a loss
  std::uint64_t refused = 0;     // readings with angles no vehicle can have (not used)
};

class AttitudeProvider {
 public:
  virtual ~AttitudeProvider() = default;

  // Opens the device (or starts the emulator). "" on success, else one line naming the
  // device and the cause. May allocate: called before the daemon is ready.
  virtual std::string open() = 0;

  // The gyro thread's job: read samples into the history until `stop` is true, checking
  // it at least every 100 ms; recovers from a lost device with backoff. No allocation.
  virtual void run(const std::atomic<bool>& stop) = 0;

  // After run() returned.
  virtual void close() = 0;

  // The sensor's angles at t_ns (the frames' clock), interpolated in the history;
  // nullopt when no reading is close enough in time. Called by the processing thread
  // while run() goes on: thread-safe, no allocation, no blocking on the reader.
  virtual std::optional<Gx1Angles> attitude_at(std::int64_t t_ns) const = 0;
  // The vehicle's yaw rate at t_ns from the gyro's angular rate, rad/s, positive turning
  // left (counter-clockwise seen from above); nullopt when the sensor reports no rate or
  // no reading is close enough in time. Same threading and allocation rules as attitude_at.
  virtual std::optional<double> yaw_rate_at(std::int64_t /*t_ns*/) const { return std::nullopt; }
  // When the newest reading was taken (the frames' clock), nullopt before the first.
  virtual std::optional<std::int64_t> newest_sample_ns() const = 0;

  virtual GyroState state() const = 0;
  // The last problem, "" when none, copied NUL-terminated (cut to fit). No allocation.
  virtual void last_problem(char* out, std::size_t size) const = 0;
  virtual GyroCounters counters() const = 0;

  // "3dm-gx1:/dev/ttyUSB0 38400 baud, continuous" for logs and status; start-up only.
  virtual std::string describe() const = 0;
};

}  // namespace ccdlane
