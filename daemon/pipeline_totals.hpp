// The pipeline's counters as one plain snapshot, for the status message and tests.
#pragma once

#include <array>
#include <cstdint>

#include "base/device_states.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

constexpr int kEstimateFailureKinds = 6;  // EstimateFailure::none .. rank_deficient

struct PipelineTotals {
  std::uint64_t frames_in = 0;         // captured into the pool
  std::uint64_t frames_processed = 0;  // estimated and handed to the sink
  std::uint64_t frames_dropped = 0;    // oldest queued frames dropped for newer ones
  std::uint64_t frames_ok = 0;
  std::uint64_t frames_unprocessed = 0;  // still queued when the pipeline stopped
  std::array<std::uint64_t, kEstimateFailureKinds> not_ok_by_reason{};
  std::uint64_t no_attitude = 0;           // processed without a gyro reading although a gyro is configured
  std::uint64_t publish_errors = 0;        // lane messages that could not be sent
  std::uint64_t frame_publish_errors = 0;  // frames ([lcm] publish_frames) that could not be sent
  std::uint64_t latency_samples_lost = 0;
  SourceCounters source;  // the source's own counters, as of its last capture
  CameraState camera = CameraState::starting;
  bool ready = false;  // the first frame has been processed
};

}  // namespace ccdlane
