// Once a second: the pipeline's totals, the latency window and the gyro's state become
// one status_t (per-period counts are differences of totals) and a one-line summary.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <ccdlane/status_t.hpp>

#include "app/attitude_provider.hpp"
#include "bus/vehicle_state_check.hpp"
#include "core/lane/online_mount_refiner.hpp"
#include "daemon/latency_window.hpp"
#include "daemon/pipeline_totals.hpp"

namespace ccdlane {

struct StatusInputs {
  std::int64_t utime = 0;      // now, microseconds since the epoch
  std::int64_t uptime_us = 0;  // since start
  PipelineTotals totals;
  LatencySummary latency;  // of the period since the previous update
  const char* camera_problem = "";
  GyroState gyro = GyroState::none;
  GyroCounters gyro_counters;
  const char* gyro_problem = "";
  GatewayCounters vehicle;  // state none: no gateway heard (or no listener)
  std::uint64_t allocations_since_ready = 0;
  calibration::OnlineMountStatus calibration;  // state off: no online refinement
};

class StatusReport {
 public:
  // Allocates the message's strings once (kStatusTextMax each); `camera` describes the
  // source for the message's camera field.
  explicit StatusReport(const std::string& camera, const std::string& instance = "");

  // The message for the period since the previous update (or since start). No allocation.
  const status_t& update(const StatusInputs& in);
  const status_t& message() const { return message_; }

  // "streaming 30.0 fps, 97% ok, 0 dropped, p99 1.2 ms, gyro ok, 0 allocations"; after gyro
  // reconnects "gyro ok (2 reconnects)"; a camera problem is appended after "; camera: ".
  void summary_line(char* out, std::size_t size) const;

 private:
  status_t message_{};
  PipelineTotals previous_;
  std::int64_t previous_uptime_us_ = 0;
};

}  // namespace ccdlane
