// The pipeline with the test-pattern source and checker: every frame in order and
// intact when processing keeps up, drops counted exactly (by sequence numbers) when it
// does not, the gyro's attitude passed through, no allocation after ready, a stalled
// camera reported, and a prompt stop. Runs under TSan in CI.
#include "daemon/pipeline.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>

#include "base/clock.hpp"
#include "base/log.hpp"
#include "daemon/allocation_counter.hpp"
#include "daemon/status_report.hpp"
#include "drivers/frames/frame_directory_source.hpp"
#include "drivers/frames/frame_directory_writer.hpp"
#include "drivers/frames/pgm.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/pipeline_doubles.hpp"
#include "tests/support/count_of.hpp"
#include "tests/support/run_process.hpp"
#include "tests/support/test_pattern_source.hpp"

namespace ccdlane {
namespace {

using namespace std::chrono_literals;
using test::CorruptingSource;
using test::eventually;
using test::FakeGyro;
using test::LockstepSource;
using test::RecordingSink;
using test::small_frames;
using test::StallingSource;
using test::WrappingSource;

// Runs a finite source to its end (and until `also` holds); the allocations counted
// after the first frame, or nullopt when it did not finish in time.
template <typename Also>
std::optional<std::uint64_t> run_to_end(Pipeline& pipeline, std::chrono::milliseconds limit, Also also) {
  pipeline.start();
  pipeline.run();
  const bool finished = eventually([&] { return pipeline.finished() && also(); }, limit);
  const std::uint64_t allocations = allocation_counter::count();
  pipeline.stop();
  allocation_counter::stop_counting();
  if (!finished) return std::nullopt;
  return allocations;
}

std::optional<std::uint64_t> run_to_end(Pipeline& pipeline, std::chrono::milliseconds limit = 10s) {
  return run_to_end(pipeline, limit, [] { return true; });
}

struct Rig {
  RealtimeConfig realtime_config;
  RealtimeSetup realtime{realtime_config};
};

TEST(Pipeline, EveryFrameArrivesInOrderAndIntactWithoutAllocating) {
  constexpr std::uint64_t kFrames = 300;
  RecordingSink sink(kFrames);
  LockstepSource source(small_frames(kFrames, 0), sink);
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor;
  Rig rig;
  PipelineOptions options;
  options.queue_depth = 2;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, options);
  EXPECT_EQ(pipeline.pool().size(), 4);
  const auto allocations = run_to_end(pipeline);
  ASSERT_TRUE(allocations.has_value()) << "did not finish";
  EXPECT_EQ(*allocations, 0u) << "the pipeline allocated after its first frame";
  const PipelineTotals t = pipeline.totals();
  EXPECT_TRUE(t.ready);
  EXPECT_EQ(t.frames_in, kFrames);
  EXPECT_EQ(t.frames_processed, kFrames);
  EXPECT_EQ(t.frames_dropped, 0u);
  EXPECT_EQ(t.frames_ok, kFrames);
  EXPECT_EQ(t.camera, CameraState::ended);
  EXPECT_EQ(t.source.frames, kFrames);
  EXPECT_EQ(processor.damaged_frames(), 0u);
  const auto records = sink.records();
  ASSERT_EQ(records.size(), kFrames);
  for (std::uint64_t i = 0; i < kFrames; ++i) {
    EXPECT_EQ(records[i].frame, i);
    EXPECT_TRUE(records[i].ok);
    EXPECT_GE(records[i].latency_us, 0);
    EXPECT_EQ(records[i].publish_utime - records[i].capture_utime, records[i].latency_us);
  }
  LatencyWindow window(1024);
  pipeline.drain_latency(window);
  EXPECT_EQ(window.take().samples, static_cast<std::int64_t>(kFrames));
}

TEST(Pipeline, WhenProcessingFallsBehindTheOldestFramesAreDroppedAndCountedExactly) {
  constexpr std::uint64_t kFrames = 3000;
  RecordingSink sink(kFrames);
  TestPatternSource source(small_frames(kFrames, 0));  // as fast as it can render
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor(/*work_us=*/300);  // far slower than that
  Rig rig;
  PipelineOptions options;
  options.queue_depth = 3;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, options);
  const auto allocations = run_to_end(pipeline, 60s);
  ASSERT_TRUE(allocations.has_value()) << "did not finish";
  EXPECT_EQ(*allocations, 0u);
  const PipelineTotals t = pipeline.totals();
  const auto records = sink.records();
  EXPECT_EQ(t.frames_in, kFrames);
  EXPECT_EQ(t.frames_processed, records.size());
  EXPECT_GT(t.frames_dropped, 0u);
  EXPECT_EQ(t.frames_processed + t.frames_dropped, kFrames) << "every frame is processed or counted as dropped";
  EXPECT_EQ(processor.damaged_frames(), 0u) << "a dropped-and-reused buffer must never reach processing torn";

  // The gaps in the published sequence numbers are exactly the drops.
  std::uint64_t gaps = records.front().frame;
  for (std::size_t i = 1; i < records.size(); ++i) {
    ASSERT_GT(records[i].frame, records[i - 1].frame) << "published out of order";
    gaps += records[i].frame - records[i - 1].frame - 1;
  }
  gaps += kFrames - 1 - records.back().frame;
  EXPECT_EQ(gaps, t.frames_dropped);
  EXPECT_EQ(records.back().frame, kFrames - 1) << "the oldest frames are dropped, never the newest";
}

TEST(Pipeline, DamagedFramesArePublishedNotOkAndCountedByReason) {
  constexpr std::uint64_t kFrames = 100;
  RecordingSink sink(kFrames);
  CorruptingSource source(small_frames(kFrames, 2000));
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor;
  Rig rig;
  PipelineOptions options;
  options.queue_depth = 62;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, options);
  ASSERT_TRUE(run_to_end(pipeline).has_value());
  const PipelineTotals t = pipeline.totals();
  const std::uint64_t damaged = processor.damaged_frames();
  EXPECT_EQ(t.frames_ok + damaged, t.frames_processed);
  EXPECT_EQ(t.not_ok_by_reason[static_cast<int>(EstimateFailure::no_frame)], damaged);
  for (const auto& r : sink.records()) {
    EXPECT_EQ(r.ok, r.frame % 10 != 9) << "frame " << r.frame;
    if (!r.ok) {
      EXPECT_EQ(r.reason, EstimateFailure::no_frame);
    }
  }
}

TEST(Pipeline, TheGyroAttitudeReachesTheProcessorOrIsCountedMissing) {
  for (const bool has_readings : {true, false}) {
    constexpr std::uint64_t kFrames = 50;
    RecordingSink sink(kFrames);
    LockstepSource source(small_frames(kFrames, 0), sink);
    ASSERT_EQ(source.open(), "");
    TestPatternProcessor processor;
    FakeGyro gyro(has_readings);
    Rig rig;
    Pipeline pipeline(source, &gyro, processor, sink, rig.realtime, PipelineOptions{});
    // On a loaded machine the 50 frames can be through before the gyro thread was first
    // scheduled; stopping then rightly skips the provider, so the end waits for it too.
    ASSERT_TRUE(run_to_end(pipeline, 10s, [&] { return gyro.running(); }).has_value());
    EXPECT_TRUE(gyro.ran()) << "the gyro thread ran the provider until stop";
    const PipelineTotals t = pipeline.totals();
    EXPECT_EQ(t.no_attitude, has_readings ? 0u : kFrames);
    for (const auto& r : sink.records()) {
      EXPECT_NEAR(r.phi_deg, has_readings ? 1.25 : 0.0, 1e-12);
      EXPECT_NEAR(r.theta_deg, has_readings ? 0.5 : 0.0, 1e-12);
    }
  }
}

// What the processor was given for the vehicle, per frame (read after the pipeline stopped).
class VehicleInputsProcessor : public TestPatternProcessor {
 public:
  explicit VehicleInputsProcessor(std::size_t capacity) { given_.reserve(capacity); }
  LaneEstimate process(const FrameInputs& in) override {
    if (given_.size() < given_.capacity()) given_.push_back(in.vehicle);
    return TestPatternProcessor::process(in);
  }
  const std::vector<VehicleInputs>& given() const { return given_; }

 private:
  std::vector<VehicleInputs> given_;
};

// Without a vehicle yaw rate the live gyro's drives the lane filter; a gyro without
// readings is a gyro fault for the warning's availability; the vehicle's own yaw rate,
// when the bus has one, wins over the gyro's.
TEST(Pipeline, TheProcessorGetsTheGyroYawRateAndHealthUnlessTheVehicleGivesItsOwn) {
  for (const bool has_readings : {true, false}) {
    constexpr std::uint64_t kFrames = 10;
    RecordingSink sink(kFrames);
    LockstepSource source(small_frames(kFrames, 0), sink);
    ASSERT_EQ(source.open(), "");
    VehicleInputsProcessor processor(kFrames);
    FakeGyro gyro(has_readings);
    Rig rig;
    Pipeline pipeline(source, &gyro, processor, sink, rig.realtime, PipelineOptions{});
    ASSERT_TRUE(run_to_end(pipeline, 10s, [&] { return gyro.running(); }).has_value());
    ASSERT_EQ(processor.given().size(), kFrames);
    for (const VehicleInputs& v : processor.given()) {
      EXPECT_EQ(v.yaw_rate_radps, has_readings ? std::optional<double>(FakeGyro::kYawRateRadps) : std::nullopt);
      EXPECT_EQ(v.gyro_ok, has_readings);
      EXPECT_TRUE(v.camera_ok);
      EXPECT_FALSE(v.speed_mps) << "no vehicle state: the configured speed applies";
    }
  }

  constexpr std::uint64_t kFrames = 10;
  lcm_t* lcm = lcm_create("memq://");
  ASSERT_NE(lcm, nullptr);
  {
    VehicleStateListener vehicle(lcm, "CCDLANE_VEHICLE");
    vehicle_state_t m{};
    m.speed_mps = 30.0;
    m.has_yaw_rate = true;
    m.yaw_rate_radps = -0.01;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    ASSERT_EQ(lcm_publish(lcm, "CCDLANE_VEHICLE", bytes.data(), static_cast<unsigned>(bytes.size())), 0);
    ASSERT_GT(lcm_handle_timeout(lcm, 1000), 0);
    RecordingSink sink(kFrames);
    LockstepSource source(small_frames(kFrames, 0), sink);
    ASSERT_EQ(source.open(), "");
    VehicleInputsProcessor processor(kFrames);
    FakeGyro gyro(true);
    Rig rig;
    Pipeline pipeline(source, &gyro, processor, sink, rig.realtime, PipelineOptions{});
    pipeline.set_vehicle_state(&vehicle, 3'600'000'000'000);
    ASSERT_TRUE(run_to_end(pipeline, 10s, [&] { return gyro.running(); }).has_value());
    ASSERT_EQ(processor.given().size(), kFrames);
    for (const VehicleInputs& v : processor.given()) {
      EXPECT_EQ(v.yaw_rate_radps, -0.01);
      EXPECT_EQ(v.speed_mps, 30.0);
    }
  }
  lcm_destroy(lcm);
}

// A played recording's own vehicle columns are its inputs, whatever the bus says now
// (the drive it was recorded on, not this one).
TEST(Pipeline, ARecordingsVehicleColumnsWinOverTheBus) {
  test::TempDir dir;
  const std::string path = dir.file("frames");
  {
    std::vector<std::uint8_t> px(64 * 48);
    FrameDirectoryWriter w(path, {true, {}, true});
    for (int i = 0; i < 4; ++i) {
      MutableImageView view{px.data(), 64, 48, 64, PixelFormat::mono8, 8};
      render_test_pattern(view, static_cast<std::uint64_t>(i));
      w.write(view, i * 5'000'000LL, Gx1Angles{0.0, 0.0, 0.0}, {}, FrameVehicle{88.0, TurnIndicator::left});
    }
    w.finish();
  }
  lcm_t* lcm = lcm_create("memq://");
  ASSERT_NE(lcm, nullptr);
  {
    VehicleStateListener vehicle(lcm, "CCDLANE_VEHICLE");
    vehicle_state_t m{};
    m.speed_mps = 5.0;
    m.turn_indicator = vehicle_state_t::TURN_INDICATOR_RIGHT;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    ASSERT_EQ(lcm_publish(lcm, "CCDLANE_VEHICLE", bytes.data(), static_cast<unsigned>(bytes.size())), 0);
    ASSERT_GT(lcm_handle_timeout(lcm, 1000), 0);
    FrameDirectorySource source({path, 200.0, false, 64, 48});
    ASSERT_EQ(source.open(), "");
    VehicleInputsProcessor processor(4);
    RecordingSink sink(4);
    Rig rig;
    Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, PipelineOptions{});
    pipeline.set_vehicle_state(&vehicle, 3'600'000'000'000);
    ASSERT_TRUE(run_to_end(pipeline).has_value());
    ASSERT_FALSE(processor.given().empty());
    for (const VehicleInputs& v : processor.given()) {
      EXPECT_EQ(v.speed_mps, 88.0 / 3.6);
      EXPECT_EQ(v.indicator, TurnIndicator::left);
    }
  }
  lcm_destroy(lcm);
}

TEST(Pipeline, AStalledCameraIsReportedWithItsProblem) {
  RecordingSink sink(1000);
  StallingSource source(small_frames(0, 500), /*frames=*/20);
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor;
  Rig rig;
  PipelineOptions options;
  options.stall_timeout_ns = 100'000'000;
  options.capture_timeout_ms = 20;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, options);
  pipeline.start();
  pipeline.run();
  char problem[256];
  pipeline.camera_problem(problem, sizeof problem);
  EXPECT_STREQ(problem, "") << "no problem while starting";
  ASSERT_TRUE(eventually([&] { return pipeline.totals().camera == CameraState::stalled; }));
  pipeline.camera_problem(problem, sizeof problem);
  EXPECT_STREQ(problem, "test: no frame since frame 19");
  pipeline.stop();
  allocation_counter::stop_counting();
  const PipelineTotals t = pipeline.totals();
  EXPECT_EQ(t.frames_in, 20u);
  EXPECT_EQ(t.frames_processed + t.frames_dropped, 20u);
  EXPECT_EQ(sink.records().back().frame, 19u);
}

// A driver that does not return from capture() (Aravis releasing a camera that stopped
// answering) cannot report anything itself: the pipeline says stalled from the age of
// the last frame, and streaming again once frames come.
class HangingSource : public TestPatternSource {
 public:
  HangingSource(const TestPatternOptions& o, std::uint64_t frames_before)
      : TestPatternSource(o), before_(frames_before) {}
  CaptureStatus capture(const MutableImageView& into, FrameMeta& meta, int timeout_ms) override {
    if (++calls_ == before_ + 1) {
      while (!release_.load()) std::this_thread::sleep_for(1ms);
    }
    return TestPatternSource::capture(into, meta, timeout_ms);
  }
  void release() { release_.store(true); }

 private:
  std::uint64_t before_;
  std::uint64_t calls_ = 0;
  std::atomic<bool> release_{false};
};

TEST(Pipeline, ACaptureCallThatDoesNotReturnIsReportedAsAStall) {
  RecordingSink sink(100000);
  HangingSource source(small_frames(0, 500), /*frames_before=*/10);
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor;
  Rig rig;
  PipelineOptions options;
  options.stall_timeout_ns = 100'000'000;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, options);
  // Released however the test ends: the pipeline's stop joins the hanging capture call.
  struct ReleaseOnExit {
    HangingSource& source;
    ~ReleaseOnExit() { source.release(); }
  } release_on_exit{source};
  pipeline.start();
  pipeline.run();
  // The first 10 frames are captured; a slow (sanitizer) build may drop some of them.
  ASSERT_TRUE(eventually([&] { return pipeline.totals().frames_in >= 10; }));
  ASSERT_TRUE(eventually([&] { return pipeline.totals().camera == CameraState::stalled; }));
  char problem[256];
  pipeline.camera_problem(problem, sizeof problem);
  EXPECT_EQ(std::string(problem).rfind("no frame for ", 0), 0u) << problem;
  EXPECT_NE(std::string(problem).find(" s (the capture call has not returned)"), std::string::npos) << problem;
  EXPECT_EQ(pipeline.totals().frames_in, 10u) << "nothing arrives while the capture call hangs";
  EXPECT_EQ(sink.count(), pipeline.totals().frames_processed);
  source.release();
  ASSERT_TRUE(eventually([&] { return pipeline.totals().frames_in >= 20; }));
  EXPECT_EQ(pipeline.totals().camera, CameraState::streaming);
  pipeline.camera_problem(problem, sizeof problem);
  EXPECT_STREQ(problem, "");
  pipeline.stop();
  allocation_counter::stop_counting();
}

// The camera's own id wraps and restarts; the daemon's frame numbers do not: unique and
// increasing for the whole run, with the camera's id kept beside them.
TEST(Pipeline, FrameNumbersStayUniqueWhenTheCamerasIdWrapsOrRestarts) {
  constexpr std::uint64_t kFrames = 200, kModulus = 16, kRestartAt = 90;
  RecordingSink sink(kFrames);
  WrappingSource source(small_frames(kFrames, 2000), kModulus, kRestartAt);
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor;
  Rig rig;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, PipelineOptions{});
  ASSERT_TRUE(run_to_end(pipeline).has_value()) << "did not finish";
  const auto records = sink.records();
  ASSERT_EQ(records.size(), pipeline.totals().frames_processed);
  ASSERT_GT(records.size(), 2 * kModulus);
  int repeated_source_ids = 0;
  for (std::size_t i = 1; i < records.size(); ++i) {
    EXPECT_GT(records[i].frame, records[i - 1].frame) << "at message " << i;
    repeated_source_ids += records[i].source_frame <= records[i - 1].source_frame;
  }
  EXPECT_GT(repeated_source_ids, 0) << "the test's source must wrap";
  EXPECT_LT(records.back().frame, kFrames) << "one number per frame captured";
  for (const auto& r : records) {
    // Frame n of the run carried the camera's id for frame n.
    const std::uint64_t n = r.frame;
    EXPECT_EQ(r.source_frame, (n >= kRestartAt ? n - kRestartAt : n) % kModulus) << "frame " << n;
    EXPECT_TRUE(r.ok) << "frame " << n;
  }
}

// Accepts every frame it is given: whatever is not ok was found bad before processing.
class AcceptingProcessor : public FrameProcessor {
 public:
  LaneEstimate process(const FrameInputs& in) override {
    LaneEstimate e;
    e.frame = in.frame;
    e.t_ns = in.t_ns;
    e.ok = true;
    return e;
  }
};

// A looping frame directory, 64x48, six frames 5 ms apart, each carrying its gyro reading.
std::string write_frames(const test::TempDir& dir, int count) {
  const std::string path = dir.file("frames");
  std::vector<std::uint8_t> px(64 * 48);
  FrameDirectoryWriter w(path, {true, {}});
  for (int i = 0; i < count; ++i) {
    MutableImageView view{px.data(), 64, 48, 64, PixelFormat::mono8, 8};
    render_test_pattern(view, static_cast<std::uint64_t>(i));
    w.write(view, i * 5'000'000LL, Gx1Angles{0.0, 0.0, 0.0});
  }
  w.finish();
  return path;
}

// The log lines written while it lives, from a temporary file.
struct CapturedLog {
  test::TempDir dir;
  std::string path = dir.file("log");
  int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  CapturedLog() { set_log_output(fd, false); }
  ~CapturedLog() {
    set_log_output(STDERR_FILENO, false);
    ::close(fd);
  }
  std::string text() const { return test::read_file(path); }
};

// Truncated, deleted and resized files in a looping directory: every one goes out as a
// lane message with ok = false (no_frame) under its own frame number, is counted in the
// status, and the first is logged naming the file (the rest within 10 s only counted).
TEST(Pipeline, BadFilesOfALoopingFrameDirectoryArePublishedCountedAndLogged) {
  test::TempDir dir;
  const std::string frames = write_frames(dir, 6);
  std::filesystem::resize_file(frames + "/000001.pgm", 20);
  std::filesystem::remove(frames + "/000003.pgm");
  std::vector<std::uint8_t> small(32 * 24, 7);
  write_pgm(frames + "/000004.pgm", ImageView{small.data(), 32, 24, 32, PixelFormat::mono8, 8});

  CapturedLog log;
  RecordingSink sink(1000);
  FrameDirectorySource source({frames, 200.0, true, 64, 48});
  ASSERT_EQ(source.open(), "");
  AcceptingProcessor processor;
  Rig rig;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, PipelineOptions{});
  pipeline.start();
  pipeline.run();
  EXPECT_TRUE(eventually([&] { return sink.count() >= 18; }));  // three passes
  pipeline.stop();

  const auto records = sink.records();
  const PipelineTotals t = pipeline.totals();
  ASSERT_EQ(records.size(), t.frames_processed);
  std::uint64_t bad = 0;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const auto& r = records[i];
    if (i > 0) {
      EXPECT_GT(r.frame, records[i - 1].frame);
    }
    const std::uint64_t row = r.source_frame % 6;
    const bool damaged = row == 1 || row == 3 || row == 4;
    EXPECT_EQ(r.ok, !damaged) << "frame " << r.frame << " (row " << row << ")";
    if (damaged) {
      EXPECT_EQ(r.reason, EstimateFailure::no_frame) << "frame " << r.frame;
      ++bad;
    }
  }
  EXPECT_GE(bad, 6u);
  EXPECT_EQ(t.frames_in, t.frames_processed + t.frames_dropped + t.frames_unprocessed) << "bad frames accounted too";

  StatusReport report(source.describe());
  StatusInputs in;
  in.totals = t;
  report.update(in);
  const status_t& s = report.message();
  EXPECT_EQ(s.not_ok_by_reason[lane_estimate_t::REASON_NO_FRAME], static_cast<std::int64_t>(bad));
  EXPECT_EQ(s.frames_not_ok_total, static_cast<std::int64_t>(bad));
  EXPECT_GE(s.source_errors_total, static_cast<std::int64_t>(bad));
  EXPECT_EQ(s.frames_processed_total - s.frames_not_ok_total, static_cast<std::int64_t>(records.size() - bad));

  const std::string text = log.text();
  EXPECT_EQ(test::count_of(text, ": bad frame "), 1) << "rate-limited: " << text;
  EXPECT_EQ(test::count_of(text, frames + "/000001.pgm: "), 1) << text;
}

// The frame directory removed while it plays: every read fails, which after
// stall_timeout is a stall, said in one line, as a camera's silence is.
TEST(Pipeline, AVanishedFrameDirectoryIsAStallAfterTheStallTimeout) {
  test::TempDir dir;
  const std::string frames = write_frames(dir, 6);
  CapturedLog log;
  RecordingSink sink(100000);
  FrameDirectorySource source({frames, 200.0, true, 64, 48});
  ASSERT_EQ(source.open(), "");
  AcceptingProcessor processor;
  Rig rig;
  PipelineOptions options;
  options.stall_timeout_ns = 300'000'000;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, options);
  pipeline.start();
  pipeline.run();
  ASSERT_TRUE(eventually([&] { return sink.count() >= 6; }));
  EXPECT_EQ(pipeline.totals().camera, CameraState::streaming);
  std::filesystem::remove_all(frames);
  const auto removed = std::chrono::steady_clock::now();
  EXPECT_TRUE(eventually([&] { return pipeline.totals().camera == CameraState::stalled; }, 3s));
  EXPECT_GE(std::chrono::steady_clock::now() - removed, 250ms) << "not before the stall timeout";
  std::this_thread::sleep_for(700ms);  // more failed reads: still one line
  char problem[256];
  pipeline.camera_problem(problem, sizeof problem);
  pipeline.stop();
  EXPECT_EQ(pipeline.totals().camera, CameraState::stalled);
  EXPECT_NE(std::string(problem).find(frames + "/"), std::string::npos) << problem;
  const std::string text = log.text();
  EXPECT_EQ(test::count_of(text, "stalled"), 1) << text;
}

TEST(Pipeline, StopsPromptlyWhileStreaming) {
  RecordingSink sink(100000);
  TestPatternSource source(small_frames(0, 200));  // endless
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor;
  Rig rig;
  Pipeline pipeline(source, nullptr, processor, sink, rig.realtime, PipelineOptions{});
  pipeline.start();
  pipeline.run();
  ASSERT_TRUE(eventually([&] { return sink.count() >= 20; }));
  const auto before = std::chrono::steady_clock::now();
  pipeline.stop();
  allocation_counter::stop_counting();
  // A requirement (shutdown within a second of SIGTERM), not a speed measurement.
  EXPECT_LT(std::chrono::steady_clock::now() - before, 1s);
  EXPECT_FALSE(pipeline.finished());
  EXPECT_EQ(pipeline.totals().camera, CameraState::streaming);
}

}  // namespace
}  // namespace ccdlane
