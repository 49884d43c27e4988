// Throughput: the daemon's pipeline, built from a configuration as ccdlaned builds it, on
// Aravis' in-process fake camera at its maximum frame rate, with a processor three times
// slower than the camera. Every processed frame must be exactly the image the fake
// rendered for its frame id (the ring never hands over a buffer that is being refilled),
// every frame must be processed, dropped or still queued at stop, with the gaps in the
// processed sequence numbers equal to the drops, and nothing may allocate after ready.
// The fake's frame ids are 16-bit GigE Vision ids and do not start at 1 (a run can wrap).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "app/config.hpp"
#include "app/source_factory.hpp"
#include "base/clock.hpp"
#include "daemon/allocation_counter.hpp"
#include "daemon/pipeline.hpp"
#include "drivers/camera/aravis_camera.hpp"
#include "tests/daemon/pipeline_doubles.hpp"
#include "tests/daemon/private_network.hpp"

namespace ccdlane {
namespace {

using namespace std::chrono_literals;

// Aravis' GigE Vision interface looks for cameras (a broadcast) before the Fake one is
// asked: in a private network namespace that stays on its own loopback.
const std::string g_network_problem = test::enter_private_network();

constexpr int kWidth = 320;  // small, so that the fake renders at its maximum rate
constexpr int kHeight = 240;

// ArvFakeCamera's default image (arv_fake_camera_diagonal_ramp, Mono8) for frame id n:
// pixel (x, y) = ((x + y + n) mod 255) * (1 + gain + log10(exposure_us / 10000)); the
// fake starts with gain 0 and a 10 ms exposure, where the scale is exactly 1.
bool is_fake_camera_frame(const ImageView& image, std::uint64_t id) {
  if (image.format != PixelFormat::mono8) return false;
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* row = image.row(y);
    for (int x = 0; x < image.width; ++x)
      if (row[x] != (static_cast<std::uint64_t>(x) + static_cast<std::uint64_t>(y) + id) % 255u) return false;
  }
  return true;
}

// Checks every pixel against the fake's image for the frame's id, and takes `work_us`
// of busy time per frame like an estimator would.
class FakeCameraFrameChecker : public FrameProcessor {
 public:
  explicit FakeCameraFrameChecker(std::int64_t work_us) : work_us_(work_us) {}
  LaneEstimate process(const FrameInputs& in) override {
    const std::int64_t until = monotonic_ns() + work_us_ * 1000;
    LaneEstimate e;
    e.frame = in.frame;
    e.t_ns = in.t_ns;
    e.ok = in.image && is_fake_camera_frame(*in.image, in.source_frame);
    if (!e.ok) {
      e.reason = EstimateFailure::no_frame;
      damaged_.fetch_add(1, std::memory_order_relaxed);
    }
    while (monotonic_ns() < until) {
    }
    return e;
  }
  std::uint64_t damaged() const { return damaged_.load(std::memory_order_relaxed); }

 private:
  std::int64_t work_us_;
  std::atomic<std::uint64_t> damaged_{0};
};

// The real driver, with the id of every frame it delivers noted (capture thread only,
// into storage reserved up front): what the processor saw is compared with it.
class CaptureLog final : public FrameSource {
 public:
  CaptureLog(FrameSource& inner, std::size_t capacity) : inner_(inner), ids_(capacity) {}
  std::string open() override { return inner_.open(); }
  int width() const override { return inner_.width(); }
  int height() const override { return inner_.height(); }
  PixelFormat format() const override { return inner_.format(); }
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override {
    const CaptureStatus s = inner_.capture(into, meta, timeout_ms);
    if (s == CaptureStatus::frame && count_ < ids_.size()) ids_[count_++] = meta.sequence;
    return s;
  }
  void close() override { inner_.close(); }
  std::string describe() const override { return inner_.describe(); }
  std::string last_problem() const override { return inner_.last_problem(); }
  SourceCounters counters() const override { return inner_.counters(); }
  // After the pipeline stopped.
  std::vector<std::uint64_t> ids() const { return {ids_.begin(), ids_.begin() + static_cast<long>(count_)}; }

 private:
  FrameSource& inner_;
  std::vector<std::uint64_t> ids_;
  std::size_t count_ = 0;
};

// Frames between two GigE Vision ids: 16 bits, skipping 0 when they wrap.
std::uint64_t ids_between(std::uint64_t last, std::uint64_t id) {
  return id > last ? id - last - 1 : (0xffff - last) + (id - 1);
}

// The fake's maximum frame rate at kWidth x kHeight, as the camera itself reports it.
double fake_camera_max_rate() {
  CameraSettings s;
  s.width = kWidth;
  s.height = kHeight;
  s.fps = 0;
  AravisCamera probe("Fake_1", s);
  if (!probe.open().empty()) return 0;
  const double max = probe.max_frame_rate();
  probe.close();
  return max;
}

TEST(PipelineThroughput, FakeCameraAtItsMaximumRateNoFrameCorruptedDropsCountedExactlyNoAllocation) {
  if (!g_network_problem.empty()) GTEST_SKIP() << g_network_problem;
  const double max_rate = fake_camera_max_rate();
  ASSERT_GT(max_rate, 100.0) << "Aravis' Fake_1 did not open";

  Config config = default_config();
  config.source.kind = SourceKind::aravis;
  config.source.camera = "Fake_1";
  config.source.rate_hz = max_rate;
  config.source.pixel_format = SourcePixels::grey;  // the checker knows the fake's mono pattern
  config.camera.Nu = kWidth;
  config.camera.Nv = kHeight;
  const std::unique_ptr<FrameSource> camera = make_frame_source(config);
  CaptureLog source(*camera, 100000);
  ASSERT_EQ(source.open(), "");

  // Three camera periods per frame: about two frames in three must be dropped.
  const auto work_us = static_cast<std::int64_t>(3e6 / max_rate);
  FakeCameraFrameChecker processor(work_us);
  test::RecordingSink sink(200000);
  RealtimeConfig realtime_config;
  RealtimeSetup realtime(realtime_config);
  Pipeline pipeline(source, nullptr, processor, sink, realtime, pipeline_options(config));
  pipeline.start();
  pipeline.run();
  ASSERT_TRUE(test::eventually([&] { return pipeline.ready(); })) << source.last_problem();
  const std::int64_t begin_ns = monotonic_ns();
  const std::uint64_t in_at_begin = pipeline.totals().frames_in;
  std::this_thread::sleep_for(2s);
  const std::uint64_t allocations = allocation_counter::count();
  const PipelineTotals before_stop = pipeline.totals();
  const std::int64_t end_ns = monotonic_ns();
  pipeline.stop();
  allocation_counter::stop_counting();
  source.close();

  const PipelineTotals t = pipeline.totals();
  const auto records = sink.records();
  const double rate =
      static_cast<double>(before_stop.frames_in - in_at_begin) / (static_cast<double>(end_ns - begin_ns) * 1e-9);
  std::printf(
      "[ figures  ] Fake_1 %dx%d at %.0f fps (its maximum): %.1f frames/s captured, %llu in, %llu processed, "
      "%llu dropped, %llu unprocessed at stop, %lld us of work per frame\n",
      kWidth, kHeight, max_rate, rate, static_cast<unsigned long long>(t.frames_in),
      static_cast<unsigned long long>(t.frames_processed), static_cast<unsigned long long>(t.frames_dropped),
      static_cast<unsigned long long>(t.frames_unprocessed), static_cast<long long>(work_us));

  EXPECT_EQ(allocations, 0u) << "allocations after ready";
  EXPECT_EQ(processor.damaged(), 0u) << "a processed frame was not the image the camera sent with its id";
  EXPECT_EQ(t.frames_ok, t.frames_processed);

  // Every frame delivered was processed, dropped or left queued, and the processor saw
  // the delivered frames in order, each at most once.
  const std::vector<std::uint64_t> captured = source.ids();
  ASSERT_EQ(captured.size(), t.frames_in);
  ASSERT_GT(t.frames_dropped, 0u) << "processing was slower than the camera";
  EXPECT_EQ(t.frames_processed + t.frames_dropped + t.frames_unprocessed, t.frames_in);
  EXPECT_LE(t.frames_unprocessed, static_cast<std::uint64_t>(config.daemon.queue_depth));
  ASSERT_EQ(records.size(), t.frames_processed);
  ASSERT_FALSE(records.empty());
  std::size_t at = 0;
  for (const auto& r : records) {
    // The camera's own id travels as source_frame (frame is the run's count).
    while (at < captured.size() && captured[at] != r.source_frame) ++at;
    ASSERT_LT(at, captured.size()) << "frame " << r.source_frame << " processed out of order, twice or never captured";
    ++at;
  }
  // The camera lost none on the way in (consecutive ids), so the gaps in the processed
  // ids are frames the pipeline did not process: exactly its drops and leftovers.
  ASSERT_EQ(t.source.dropped, 0u);
  ASSERT_EQ(t.source.errors, 0u);
  for (std::size_t i = 1; i < captured.size(); ++i) ASSERT_EQ(ids_between(captured[i - 1], captured[i]), 0u) << i;
  std::uint64_t gaps = records.front().source_frame == captured.front()
                           ? 0
                           : ids_between(captured.front(), records.front().source_frame) + 1;
  for (std::size_t i = 1; i < records.size(); ++i)
    gaps += ids_between(records[i - 1].source_frame, records[i].source_frame);
  if (records.back().source_frame != captured.back())
    gaps += ids_between(records.back().source_frame, captured.back()) + 1;
  EXPECT_EQ(gaps, t.frames_dropped + t.frames_unprocessed) << "every frame not processed is a counted drop";
  EXPECT_EQ(t.camera, CameraState::streaming);
}

}  // namespace
}  // namespace ccdlane
