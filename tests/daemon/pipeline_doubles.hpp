// Test doubles around the pipeline: a recording sink, sources that go in lockstep,
// stall or damage frames, and a gyro that answers (or not).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "app/attitude_provider.hpp"
#include "base/clock.hpp"
#include "bus/lane_sink.hpp"
#include "tests/support/test_pattern_source.hpp"

namespace ccdlane::test {

// What the processing thread published, into storage reserved up front.
class RecordingSink : public LaneSink {
 public:
  struct Record {
    std::uint64_t frame;
    bool ok;
    EstimateFailure reason;
    double theta_deg, phi_deg;
    std::int64_t latency_us, capture_utime, publish_utime;
    std::uint64_t source_frame;
    bool roll_unobservable;
  };
  explicit RecordingSink(std::size_t capacity) : records_(capacity) {}
  bool publish_lane(const LaneEstimate& e, std::int64_t capture_utime, std::int64_t publish_utime) override {
    const std::uint64_t n = count_.load(std::memory_order_relaxed);
    if (n >= records_.size()) return false;
    records_[n] = Record{e.frame,      e.ok,          e.reason,      e.theta_deg,    e.phi_deg,
                         e.latency_us, capture_utime, publish_utime, e.source_frame, e.roll_unobservable};
    count_.store(n + 1, std::memory_order_release);
    return true;
  }
  std::uint64_t count() const { return count_.load(std::memory_order_acquire); }
  std::vector<Record> records() const { return {records_.begin(), records_.begin() + static_cast<long>(count())}; }

 private:
  std::vector<Record> records_;
  std::atomic<std::uint64_t> count_{0};
};

inline TestPatternOptions small_frames(std::uint64_t frames, double rate_hz) {
  TestPatternOptions o;
  o.width = 64;
  o.height = 48;
  o.rate_hz = rate_hz;
  o.frames = frames;
  return o;
}

// Hands out frame n only once frame n-1 was published: processing can never fall behind,
// whatever the machine's load, so nothing may be dropped.
class LockstepSource : public TestPatternSource {
 public:
  LockstepSource(const TestPatternOptions& o, const RecordingSink& sink) : TestPatternSource(o), sink_(sink) {}
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override {
    const std::int64_t deadline = monotonic_ns() + timeout_ms * 1'000'000LL;
    while (sink_.count() < handed_out_) {
      if (monotonic_ns() > deadline) return CaptureStatus::timeout;
      std::this_thread::sleep_for(std::chrono::microseconds(20));
    }
    const CaptureStatus s = TestPatternSource::capture(into, meta, timeout_ms);
    if (s == CaptureStatus::frame) ++handed_out_;
    return s;
  }

 private:
  const RecordingSink& sink_;
  std::uint64_t handed_out_ = 0;
};

// Streams `frames` frames, then delivers nothing (a camera that stopped).
class StallingSource : public TestPatternSource {
 public:
  StallingSource(const TestPatternOptions& o, std::uint64_t frames) : TestPatternSource(o), frames_(frames) {}
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override {
    if (delivered_ >= frames_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
      return CaptureStatus::timeout;
    }
    ++delivered_;
    return TestPatternSource::capture(into, meta, timeout_ms);
  }
  std::string last_problem() const override { return "test: no frame since frame " + std::to_string(frames_ - 1); }

 private:
  std::uint64_t frames_;
  std::uint64_t delivered_ = 0;
};

// Every 10th frame carries the previous frame's pixels: a damaged frame.
class CorruptingSource : public TestPatternSource {
 public:
  using TestPatternSource::TestPatternSource;
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override {
    const CaptureStatus s = TestPatternSource::capture(into, meta, timeout_ms);
    if (s == CaptureStatus::frame && meta.sequence % 10 == 9) render_test_pattern(into, meta.sequence - 1);
    return s;
  }
};

// A camera whose own frame id wraps at `modulus` (as Aravis' 16-bit block id does) and
// jumps back to 0 at frame `restart_at` (as after a camera restart).
class WrappingSource : public TestPatternSource {
 public:
  WrappingSource(const TestPatternOptions& o, std::uint64_t modulus, std::uint64_t restart_at)
      : TestPatternSource(o), modulus_(modulus), restart_at_(restart_at) {}
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override {
    const CaptureStatus s = TestPatternSource::capture(into, meta, timeout_ms);
    if (s != CaptureStatus::frame) return s;
    const std::uint64_t n = meta.sequence;
    meta.sequence = (n >= restart_at_ ? n - restart_at_ : n) % modulus_;
    render_test_pattern(into, meta.sequence);  // intact under the number it carries
    return s;
  }

 private:
  std::uint64_t modulus_, restart_at_;
};

class FakeGyro : public AttitudeProvider {
 public:
  explicit FakeGyro(bool has_readings) : has_readings_(has_readings) {}
  std::string open() override { return ""; }
  void run(const std::atomic<bool>& stop) override {
    running_.store(true);
    while (!stop.load()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    running_.store(false);
    ran_.store(true);
  }
  void close() override {}
  std::optional<Gx1Angles> attitude_at(std::int64_t) const override {
    if (!has_readings_) return std::nullopt;
    return Gx1Angles{1.25, -0.5, 90.0};
  }
  std::optional<double> yaw_rate_at(std::int64_t) const override {
    return has_readings_ ? std::optional<double>(kYawRateRadps) : std::nullopt;
  }
  std::optional<std::int64_t> newest_sample_ns() const override {
    return has_readings_ ? std::optional<std::int64_t>(monotonic_ns()) : std::nullopt;
  }
  static constexpr double kYawRateRadps = 0.03;
  GyroState state() const override { return has_readings_ ? GyroState::ok : GyroState::stale; }
  void last_problem(char* out, std::size_t size) const override { std::snprintf(out, size, "%s", ""); }
  GyroCounters counters() const override { return {}; }
  std::string describe() const override { return "fake gyro"; }
  bool running() const { return running_.load(); }
  bool ran() const { return ran_.load(); }

 private:
  bool has_readings_;
  std::atomic<bool> running_{false}, ran_{false};
};

// Waits (bounded) for a condition the pipeline's threads bring about.
template <typename Condition>
bool eventually(Condition condition, std::chrono::milliseconds limit = std::chrono::seconds(10)) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

}  // namespace ccdlane::test
