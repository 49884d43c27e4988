// Buffer ownership is the whole design: a buffer index is held by exactly one of the
// capture thread, the queue, the processing thread or the return ring, and moves only
// through the rings' release/acquire pairs, which is what makes plain pixel writes safe.
#include "daemon/pipeline.hpp"

#include <pthread.h>

#include <cstdio>
#include <exception>
#include <stdexcept>

#include "app/frame_inputs.hpp"
#include "base/clock.hpp"
#include "base/log.hpp"
#include "daemon/allocation_counter.hpp"

namespace ccdlane {
namespace {

FramePoolLayout pool_layout(const FrameSource& source, int queue_depth) {
  FramePoolLayout layout;
  // One buffer being filled, one being processed, queue_depth waiting: with this many the
  // capture thread always finds a free buffer after queueing one.
  layout.count = queue_depth + 2;
  layout.width = source.width();
  layout.height = source.height();
  layout.format = source.format();
  return layout;
}

void name_this_thread(const char* name) { pthread_setname_np(pthread_self(), name); }

}  // namespace

PipelineOptions pipeline_options(const Config& c) {
  PipelineOptions o;
  o.queue_depth = c.daemon.queue_depth;
  o.stall_timeout_ns = static_cast<std::int64_t>(c.daemon.stall_timeout_s * 1e9);
  o.capture_priority = c.realtime.capture_priority;
  o.processing_priority = c.realtime.processing_priority;
  o.gyro_priority = c.realtime.gyro_priority;
  return o;
}

Pipeline::Pipeline(FrameSource& source, AttitudeProvider* gyro, FrameProcessor& processor, LaneSink& sink,
                   RealtimeSetup& realtime, const PipelineOptions& options)
    : source_(source),
      gyro_(gyro),
      processor_(processor),
      sink_(sink),
      realtime_(realtime),
      options_(options),
      camera_name_(source.describe()),
      pool_(pool_layout(source, options.queue_depth)),
      slots_(static_cast<std::size_t>(pool_.size())),
      queued_(static_cast<std::size_t>(options.queue_depth)),
      returned_(static_cast<std::size_t>(pool_.size())),
      latencies_(options.latency_queue) {
  if (options.queue_depth < 1) throw std::invalid_argument("pipeline: queue_depth must be at least 1");
  for (int i = 0; i < pool_.size(); ++i) {
    if (!returned_.try_push(static_cast<std::uint32_t>(i))) throw std::logic_error("pipeline: return ring too small");
  }
}

Pipeline::~Pipeline() { stop(); }

void Pipeline::start() {
  threads_.emplace_back([this] { capture_loop(); });
  threads_.emplace_back([this] { processing_loop(); });
  if (gyro_) threads_.emplace_back([this] { gyro_loop(); });
}

void Pipeline::run() {
  go_.store(true, std::memory_order_release);
  go_bell_.ring();
}

void Pipeline::stop() {
  if (stopped_) return;
  stopped_ = true;
  stop_.store(true, std::memory_order_release);
  run();  // threads still waiting to start see stop_ at once
  frame_bell_.ring();
  for (std::thread& t : threads_) t.join();
  threads_.clear();
  // Joined, so this thread may take the consumer's side: what capture queued after
  // processing last looked is counted, so that in = processed + dropped + unprocessed.
  std::uint32_t index = 0;
  while (queued_.try_pop(index)) {
    frames_unprocessed_.fetch_add(1, std::memory_order_relaxed);
    if (!returned_.try_push(index)) std::terminate();  // holds the whole pool: cannot be full
  }
}

void Pipeline::wait_for_run() {
  for (;;) {
    const std::uint32_t seen = go_bell_.value();
    if (go_.load(std::memory_order_acquire)) return;
    go_bell_.wait(seen, 100);
  }
}

void Pipeline::set_camera_state(CameraState state) {
  if (camera_state_.load(std::memory_order_relaxed) == state) return;
  // Copied, not returned as a string: a camera that comes and goes must not make the
  // allocation count of the status move.
  char problem[sizeof problem_] = "";
  if (state != CameraState::streaming) source_.copy_last_problem(problem, sizeof problem);
  // The pipeline may call a stall before the driver has a word for it.
  if (state == CameraState::stalled && problem[0] == '\0')
    std::snprintf(problem, sizeof problem, "no frame for %.1f s",
                  static_cast<double>(options_.stall_timeout_ns) * 1e-9);
  {
    std::lock_guard<std::mutex> lock(problem_mutex_);
    std::snprintf(problem_, sizeof problem_, "%s", problem);
  }
  // The state after its problem: whoever sees the new state (totals(), acquiring) finds
  // the problem that goes with it (a status read between the two said stalled, and "").
  const CameraState before = camera_state_.exchange(state, std::memory_order_release);
  if (state == CameraState::streaming) {
    if (before != CameraState::starting)
      log_line(LogLevel::notice, "camera", "%s: streaming again", camera_name_.c_str());
  } else if (state == CameraState::ended) {
    log_line(LogLevel::info, "camera", "%s: end of stream", camera_name_.c_str());
  } else {
    log_line(LogLevel::warning, "camera", "%s: %s%s%s", camera_name_.c_str(), to_string(state),
             problem[0] == '\0' ? "" : ": ", problem);
  }
}

void Pipeline::capture_loop() {
  name_this_thread("ccd-capture");
  realtime_.apply_to_current_thread("capture", options_.capture_priority);
  wait_for_run();
  std::uint32_t current = 0;
  if (!returned_.try_pop(current)) return;  // impossible: the return ring starts full
  std::int64_t last_frame_ns = monotonic_ns();

  while (!stop_.load(std::memory_order_acquire)) {
    FrameMeta meta;
    capture_call_ns_.store(monotonic_ns(), std::memory_order_relaxed);
    const CaptureStatus status =
        source_.capture(pool_.view(static_cast<int>(current)), meta, options_.capture_timeout_ms);
    capture_call_ns_.store(0, std::memory_order_relaxed);
    const std::int64_t now = monotonic_ns();
    const SourceCounters c = source_.counters();
    source_frames_.store(c.frames, std::memory_order_relaxed);
    source_dropped_.store(c.dropped, std::memory_order_relaxed);
    source_errors_.store(c.errors, std::memory_order_relaxed);
    source_timeouts_.store(c.timeouts, std::memory_order_relaxed);
    source_reconnects_.store(c.reconnects, std::memory_order_relaxed);

    switch (status) {
      case CaptureStatus::frame: {
        last_frame_ns = now;
        last_frame_ns_.store(now, std::memory_order_relaxed);
        slots_[current] = SlotMeta{meta, now, next_frame_++};
        frames_in_.fetch_add(1, std::memory_order_relaxed);
        set_camera_state(CameraState::streaming);
        if (!queue_current(current)) return;
        break;
      }
      case CaptureStatus::timeout:
        if (now - last_frame_ns >= options_.stall_timeout_ns) set_camera_state(CameraState::stalled);
        break;
      case CaptureStatus::recovering: set_camera_state(CameraState::recovering); break;
      case CaptureStatus::error: {
        // Counted by the source; the next frame may be fine. The bad one still takes its
        // frame number and goes out as a lane message with ok = false, so that a
        // subscriber sees it instead of a gap that looks like a drop.
        slots_[current] = SlotMeta{meta, now, next_frame_++, true};
        if (slots_[current].meta.t_ns == 0) slots_[current].meta.t_ns = now;
        frames_in_.fetch_add(1, std::memory_order_relaxed);
        // Nothing but bad frames for stall_timeout (a frame directory removed, a camera
        // sending only garbage) is a stall, as silence is: one line, then quiet.
        if (now - last_frame_ns >= options_.stall_timeout_ns) set_camera_state(CameraState::stalled);
        if (camera_state_.load(std::memory_order_relaxed) != CameraState::stalled) report_bad_frame(now);
        if (!queue_current(current)) return;
        break;
      }
      case CaptureStatus::end_of_stream:
        set_camera_state(CameraState::ended);
        capture_ended_.store(true, std::memory_order_release);
        frame_bell_.ring();
        return;
    }
  }
}

bool Pipeline::queue_current(std::uint32_t& current) {
  if (const auto oldest = queued_.push_dropping_oldest(current)) {
    // Processing is behind: the oldest waiting frame made room, its buffer is ours.
    frames_dropped_.fetch_add(1, std::memory_order_relaxed);
    current = *oldest;
  } else {
    // Pool sizing guarantees a free buffer now; wait rather than overwrite a buffer
    // someone else owns should that reasoning ever be wrong.
    while (!returned_.try_pop(current)) {
      if (stop_.load(std::memory_order_acquire)) return false;
      std::this_thread::yield();
    }
  }
  frame_bell_.ring();
  return true;
}

void Pipeline::report_bad_frame(std::int64_t now_ns) {
  // A directory of damaged files (or a camera sending garbage) must not flood the log:
  // the first line names the file and cause, later ones say how many went unsaid.
  if (bad_frame_logged_ns_ != 0 && now_ns - bad_frame_logged_ns_ < kBadFrameLogPeriodNs) {
    ++bad_frames_unlogged_;
    return;
  }
  char problem[sizeof problem_] = "";
  source_.copy_last_problem(problem, sizeof problem);
  if (bad_frames_unlogged_ > 0)
    log_line(LogLevel::warning, "camera", "%s: bad frame %llu: %s (and %llu more bad frames since the last such line)",
             camera_name_.c_str(), static_cast<unsigned long long>(next_frame_ - 1), problem,
             static_cast<unsigned long long>(bad_frames_unlogged_));
  else
    log_line(LogLevel::warning, "camera", "%s: bad frame %llu: %s", camera_name_.c_str(),
             static_cast<unsigned long long>(next_frame_ - 1), problem);
  bad_frame_logged_ns_ = now_ns;
  bad_frames_unlogged_ = 0;
}

void Pipeline::processing_loop() {
  name_this_thread("ccd-process");
  realtime_.apply_to_current_thread("processing", options_.processing_priority);
  wait_for_run();
  std::uint32_t index = 0;
  for (;;) {
    // Read the doorbell before looking: a frame queued after the look changes it, so the
    // wait below cannot sleep through it.
    const std::uint32_t bell = frame_bell_.value();
    if (queued_.try_pop(index)) {
      process_one(index);
      continue;
    }
    if (stop_.load(std::memory_order_acquire)) return;
    if (capture_ended_.load(std::memory_order_acquire)) {
      // Frames queued before the end was announced are visible now.
      if (queued_.try_pop(index)) {
        process_one(index);
        continue;
      }
      finished_.store(true, std::memory_order_release);
      return;
    }
    frame_bell_.wait(bell, 100);  // the timeout only bounds a wait nobody rings for
  }
}

LiveReadings Pipeline::live_readings(const SlotMeta& slot) {
  LiveReadings live;
  // A recording plays with the vehicle it was made with, whatever is on the bus now.
  if (!slot.meta.speed_kmh && !slot.meta.indicator && vehicle_state_)
    live.vehicle = vehicle_inputs(*vehicle_state_, monotonic_ns(), vehicle_state_max_age_ns_);
  if (!gyro_) return live;
  const GyroState g = gyro_->state();
  live.gyro_delivering = g != GyroState::stale && g != GyroState::lost;
  // A recording's frames carry their own reading, and were not turned by this gyro.
  if (slot.bad || slot.meta.gyro) return live;
  live.gyro = gyro_->attitude_at(slot.meta.t_ns);
  if (!live.gyro) no_attitude_.fetch_add(1, std::memory_order_relaxed);
  live.yaw_rate_radps = gyro_->yaw_rate_at(slot.meta.t_ns);
  return live;
}

void Pipeline::process_one(std::uint32_t index) {
  const SlotMeta slot = slots_[index];
  const ImageView image = pool_.view(static_cast<int>(index));
  const FrameInputs in =
      frame_inputs(slot.bad ? nullptr : &image, slot.frame, slot.meta, live_readings(slot), gyro_ != nullptr);
  if (slot.bad) {
    if (!returned_.try_push(index)) std::terminate();  // holds the whole pool: cannot be full
    // The lane departure warning coasts through it, and says the camera failed.
    LaneEstimate estimate = processor_.no_frame(in);
    estimate.source_frame = slot.meta.sequence;  // for processors other than the estimator
    publish(estimate, slot.received_ns);
    return;
  }
  const VehicleInputs& vehicle = in.vehicle;
  // The source's id may wrap (a 16-bit block id) or restart with the camera: messages go
  // out under the run's own count, with the source's id beside it.
  LaneEstimate estimate = processor_.process(in);
  estimate.source_frame = slot.meta.sequence;  // for processors other than the estimator
  if (sink_.publishes_frames()) {
    // Only processed frames go out, in processing order (after any drop), keyed as the
    // lane message is: the log holds the very frame stream the estimator's tracking saw,
    // with the vehicle inputs it was given, so that replay warns as the daemon did.
    FrameRecord record{slot.frame, slot.meta.frame_t_ns(), realtime_us_of_monotonic(slot.meta.t_ns), in.gyro,
                       slot.meta.sequence};
    if (vehicle.speed_mps) record.speed_kmh = *vehicle.speed_mps * 3.6;
    record.yaw_rate_radps = vehicle.yaw_rate_radps;
    record.indicator = vehicle.indicator;
    if (!sink_.publish_frame(image, record)) frame_publish_errors_.fetch_add(1, std::memory_order_relaxed);
  }
  // The pixels are no longer needed: give the buffer back before publishing the lanes.
  if (!returned_.try_push(index)) std::terminate();  // holds the whole pool: cannot be full
  publish(estimate, slot.received_ns);

  if (!ready_.load(std::memory_order_relaxed)) {
    // Everything is allocated and every lazy first-use path has run once: from here on,
    // any allocation is a defect, and the status says how many there were.
    allocation_counter::start_counting();
    ready_.store(true, std::memory_order_release);
    log_line(LogLevel::info, "pipeline", "ready: first frame processed (%s)", camera_name_.c_str());
  }
}

void Pipeline::publish(LaneEstimate& estimate, std::int64_t received_ns) {
  estimate.latency_us = (monotonic_ns() - received_ns) / 1000;
  const std::int64_t publish_utime = realtime_us();
  if (!sink_.publish_lane(estimate, publish_utime - estimate.latency_us, publish_utime))
    publish_errors_.fetch_add(1, std::memory_order_relaxed);
  const std::int64_t published_ns = monotonic_ns();

  frames_processed_.fetch_add(1, std::memory_order_relaxed);
  if (estimate.ok)
    frames_ok_.fetch_add(1, std::memory_order_relaxed);
  else
    not_ok_by_reason_[static_cast<int>(estimate.reason) % kEstimateFailureKinds].fetch_add(1,
                                                                                           std::memory_order_relaxed);
  // The statistics measure up to the end of the publish call, which the message's own
  // latency_us (encoded before sending) cannot include.
  if (!latencies_.try_push((published_ns - received_ns) / 1000))
    latency_samples_lost_.fetch_add(1, std::memory_order_relaxed);
}

void Pipeline::gyro_loop() {
  name_this_thread("ccd-gyro");
  realtime_.apply_to_current_thread("gyro", options_.gyro_priority);
  wait_for_run();
  if (!stop_.load(std::memory_order_acquire)) gyro_->run(stop_);
}

PipelineTotals Pipeline::totals() const {
  PipelineTotals t;
  t.frames_in = frames_in_.load(std::memory_order_relaxed);
  t.frames_processed = frames_processed_.load(std::memory_order_relaxed);
  t.frames_dropped = frames_dropped_.load(std::memory_order_relaxed);
  t.frames_ok = frames_ok_.load(std::memory_order_relaxed);
  t.frames_unprocessed = frames_unprocessed_.load(std::memory_order_relaxed);
  for (int i = 0; i < kEstimateFailureKinds; ++i)
    t.not_ok_by_reason[static_cast<std::size_t>(i)] = not_ok_by_reason_[i].load(std::memory_order_relaxed);
  t.no_attitude = no_attitude_.load(std::memory_order_relaxed);
  t.publish_errors = publish_errors_.load(std::memory_order_relaxed);
  t.frame_publish_errors = frame_publish_errors_.load(std::memory_order_relaxed);
  t.latency_samples_lost = latency_samples_lost_.load(std::memory_order_relaxed);
  t.source.frames = source_frames_.load(std::memory_order_relaxed);
  t.source.dropped = source_dropped_.load(std::memory_order_relaxed);
  t.source.errors = source_errors_.load(std::memory_order_relaxed);
  t.source.timeouts = source_timeouts_.load(std::memory_order_relaxed);
  t.source.reconnects = source_reconnects_.load(std::memory_order_relaxed);
  t.camera = camera_state_.load(std::memory_order_acquire);
  if (stuck_silence_ns() >= options_.stall_timeout_ns) t.camera = CameraState::stalled;
  t.ready = ready();
  return t;
}

void Pipeline::drain_latency(LatencyWindow& window) {
  std::int64_t us = 0;
  while (latencies_.try_pop(us)) window.add(us);
}

std::int64_t Pipeline::stuck_silence_ns() const {
  if (camera_state_.load(std::memory_order_relaxed) != CameraState::streaming) return 0;
  const std::int64_t call = capture_call_ns_.load(std::memory_order_relaxed);
  const std::int64_t last = last_frame_ns_.load(std::memory_order_relaxed);
  const std::int64_t now = monotonic_ns();
  if (call == 0 || last == 0 || now - call <= 2 * std::int64_t{options_.capture_timeout_ms} * 1'000'000) return 0;
  return now - last;
}

void Pipeline::camera_problem(char* out, std::size_t size) const {
  if (size == 0) return;
  if (const std::int64_t silent = stuck_silence_ns(); silent >= options_.stall_timeout_ns) {
    std::snprintf(out, size, "no frame for %.1f s (the capture call has not returned)",
                  static_cast<double>(silent) * 1e-9);
    return;
  }
  std::lock_guard<std::mutex> lock(problem_mutex_);
  std::snprintf(out, size, "%s", problem_);
}

}  // namespace ccdlane
