// The real-time pipeline: a capture thread fills buffers of a fixed pool and queues
// their indices, a processing thread turns each frame into a lane estimate and
// publishes it, a gyro thread keeps the attitude history; rings carry buffer indices
// between them, and nothing allocates once the first frame is through.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "app/attitude_provider.hpp"
#include "app/config.hpp"
#include "app/frame_inputs.hpp"
#include "base/spsc_ring.hpp"
#include "bus/lane_sink.hpp"
#include "bus/vehicle_state_listener.hpp"
#include "daemon/doorbell.hpp"
#include "daemon/frame_processor.hpp"
#include "daemon/latency_window.hpp"
#include "daemon/pipeline_totals.hpp"
#include "daemon/realtime.hpp"
#include "drivers/camera/frame_pool.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

struct PipelineOptions {
  int queue_depth = 4;                            // frames waiting for processing; beyond, the oldest is dropped
  int capture_timeout_ms = 100;                   // bounds how long stop() waits for the capture thread
  std::int64_t stall_timeout_ns = 2'000'000'000;  // no frame for this long: camera stalled
  int capture_priority = 0;                       // SCHED_FIFO priorities, 0 = normal scheduling
  int processing_priority = 0;
  int gyro_priority = 0;
  std::size_t latency_queue = 16384;  // latency samples waiting for the status thread
};

// The options ccdlaned runs its pipeline with: [daemon] and [realtime].
PipelineOptions pipeline_options(const Config& config);

class Pipeline {
 public:
  static constexpr std::int64_t kBadFrameLogPeriodNs = 10'000'000'000;

  // Allocates everything the threads will use: queue_depth + 2 frames of the (open)
  // source's size, the rings and the latency queue. `gyro` may be null (no gyro).
  Pipeline(FrameSource& source, AttitudeProvider* gyro, FrameProcessor& processor, LaneSink& sink,
           RealtimeSetup& realtime, const PipelineOptions& options);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Where frames that carry no recorded vehicle values (live cameras) take their speed,
  // yaw rate and indicator: the bus's latest vehicle state (a CAN gateway's
  // vehicle_state_t), none when it is older than max_age_ns. Without one, or stale:
  // [vehicle] speed_kmh, no indicator; and once the gateway was heard, LDW is unavailable
  // (vehicle_fault) while no good state is fresh. Call before start(); `listener` must
  // outlive stop().
  void set_vehicle_state(const VehicleStateListener* listener, std::int64_t max_age_ns) {
    vehicle_state_ = listener;
    vehicle_state_max_age_ns_ = max_age_ns;
  }

  // Creates the threads; each applies its real-time settings, then waits for run().
  void start();
  // Lets the threads go (call after RealtimeSetup::lock_memory, so that locking cannot
  // make a thread's creation fail).
  void run();
  // Stops and joins every thread: within capture_timeout_ms plus one frame's processing.
  // Frames still queued are not processed (totals().frames_unprocessed). Idempotent.
  void stop();

  // A finite source ended and every frame it delivered was processed or dropped.
  bool finished() const { return finished_.load(std::memory_order_acquire); }
  // The first frame has been processed (allocations are counted from then on).
  bool ready() const { return ready_.load(std::memory_order_acquire); }

  PipelineTotals totals() const;
  // Moves the latency samples gathered since the last call into `window` (one reader).
  void drain_latency(LatencyWindow& window);
  // The source's last problem as the capture thread last saw it; "" while streaming.
  // When a streaming camera has given no frame for stall_timeout_ns and the capture call
  // has overrun its timeout (a driver blocked inside a device that stopped answering),
  // the camera is reported stalled from here: the capture thread cannot say so itself.
  void camera_problem(char* out, std::size_t size) const;
  const FramePool& pool() const { return pool_; }

 private:
  struct SlotMeta {
    FrameMeta meta;
    std::int64_t received_ns = 0;  // CLOCK_MONOTONIC when capture() returned the frame
    std::uint64_t frame = 0;       // the run's frame number (meta.sequence is the source's own)
    bool bad = false;              // capture() said error: no pixels, published ok = false (no_frame)
  };

  void capture_loop();
  void processing_loop();
  void gyro_loop();
  void process_one(std::uint32_t index);
  // What the gyro and the bus know at the frame (app/frame_inputs.hpp's LiveReadings);
  // counts a frame the live gyro has no reading for.
  LiveReadings live_readings(const SlotMeta& slot);
  // Sends one estimate (every frame's, bad ones included) and counts it.
  void publish(LaneEstimate& estimate, std::int64_t received_ns);
  // Hands the filled buffer to processing and takes a free one; false when stopping.
  bool queue_current(std::uint32_t& current);
  // A bad frame: logged at most every kBadFrameLogPeriodNs, with how many went unsaid.
  void report_bad_frame(std::int64_t now_ns);
  void set_camera_state(CameraState state);
  // How long a camera said to be streaming has been without a frame while the capture
  // call is stuck (past twice its timeout); 0 otherwise.
  std::int64_t stuck_silence_ns() const;
  void wait_for_run();

  FrameSource& source_;
  AttitudeProvider* gyro_;
  const VehicleStateListener* vehicle_state_ = nullptr;
  std::int64_t vehicle_state_max_age_ns_ = 0;
  FrameProcessor& processor_;
  LaneSink& sink_;
  RealtimeSetup& realtime_;
  const PipelineOptions options_;
  const std::string camera_name_;

  // The camera drivers' pool, for its storage only: buffers change hands through the
  // two rings below, so its borrow()/give_back() are not used here.
  FramePool pool_;
  std::vector<SlotMeta> slots_;       // per buffer; written by capture, read by processing
  SpscRing<std::uint32_t> queued_;    // capture -> processing (drop-oldest)
  SpscRing<std::uint32_t> returned_;  // processing -> capture (never full: holds the pool)
  SpscRing<std::int64_t> latencies_;  // processing -> status thread, microseconds

  Doorbell frame_bell_;  // rung on every queued frame, at the end of the source and on stop
  Doorbell go_bell_;     // rung by run() and stop()
  std::atomic<bool> go_{false}, stop_{false}, capture_ended_{false}, finished_{false}, ready_{false};
  bool stopped_ = false;

  // Counters: one writer each, read by the status thread.
  std::atomic<std::uint64_t> frames_in_{0}, frames_processed_{0}, frames_dropped_{0}, frames_ok_{0},
      frames_unprocessed_{0};
  std::atomic<std::uint64_t> not_ok_by_reason_[kEstimateFailureKinds] = {};
  std::atomic<std::uint64_t> no_attitude_{0}, publish_errors_{0}, frame_publish_errors_{0}, latency_samples_lost_{0};
  std::atomic<std::uint64_t> source_frames_{0}, source_dropped_{0}, source_errors_{0}, source_timeouts_{0},
      source_reconnects_{0};
  std::uint64_t next_frame_ = 0;           // the capture thread's: the next frame number of this run
  std::int64_t bad_frame_logged_ns_ = 0;   // the capture thread's: last bad-frame log line
  std::uint64_t bad_frames_unlogged_ = 0;  //   and the bad frames since, not logged
  std::atomic<CameraState> camera_state_{CameraState::starting};
  std::atomic<std::int64_t> last_frame_ns_{0};    // CLOCK_MONOTONIC of the last frame captured
  std::atomic<std::int64_t> capture_call_ns_{0};  // when the current capture() call began; 0 between calls

  mutable std::mutex problem_mutex_;  // taken only on camera state changes and by status
  char problem_[256] = {};

  std::vector<std::thread> threads_;
};

}  // namespace ccdlane
