// The daemon's pipeline at 60 fps on 800x600 frames for a fixed time, publishing on the
// default udpm bus: capture -> publish latency (p50/p99/max), CPU use and drops, with
// normal scheduling and with SCHED_FIFO (where permitted). Plus the ring's own cost.
//
//   build/tests/bench/daemon/daemon_pipeline_bench [--benchmark_filter=Pipeline]
//
// Processing is the daemon's own: the lane estimator (detect, solve, track) on the built-in
// synthetic road (4 s of the default drive, rendered before the clock starts, replayed at
// 60 fps), with each frame's gyro reading as the priors.
#include <sys/resource.h>

#include <chrono>
#include <thread>

#include <benchmark/benchmark.h>

#include "app/synth_source.hpp"
#include "base/clock.hpp"
#include "base/spsc_ring.hpp"
#include "bus/lcm_publisher.hpp"
#include "daemon/allocation_counter.hpp"
#include "daemon/frame_processor.hpp"
#include "daemon/pipeline.hpp"

namespace ccdlane {
namespace {

double cpu_seconds() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  return static_cast<double>(r.ru_utime.tv_sec + r.ru_stime.tv_sec) +
         static_cast<double>(r.ru_utime.tv_usec + r.ru_stime.tv_usec) * 1e-6;
}

// Arguments: seconds to run, SCHED_FIFO priority for capture/processing (0 = normal).
void BM_Pipeline800x600At60Fps(benchmark::State& state) {
  const auto seconds = state.range(0);
  const int priority = static_cast<int>(state.range(1));
  for (auto _ : state) {
    Config config = default_config();  // the reference camera: 800x600
    config.synth.frames = 1000;        // as many as the source renders (4 s of the drive)
    SynthSourceOptions o;
    o.rate_hz = 60.0;
    SynthSource source(config, o);
    if (!source.open().empty()) state.SkipWithError("source");
    EstimatorProcessor processor(config, source);
    LcmPublisher publisher(LcmConfig{});
    RealtimeConfig rt_config;
    rt_config.capture_priority = priority;
    rt_config.processing_priority = priority > 0 ? priority - 1 : 0;
    RealtimeSetup realtime(rt_config);
    PipelineOptions options;
    options.capture_priority = rt_config.capture_priority;
    options.processing_priority = rt_config.processing_priority;
    Pipeline pipeline(source, nullptr, processor, publisher, realtime, options);
    LatencyWindow window(1 << 16);

    const double cpu0 = cpu_seconds();
    const std::int64_t t0 = monotonic_ns();
    pipeline.start();
    pipeline.run();
    for (std::int64_t s = 0; s < seconds * 10; ++s) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      pipeline.drain_latency(window);
    }
    const std::uint64_t allocations = allocation_counter::count();
    pipeline.stop();
    allocation_counter::stop_counting();
    const double wall = static_cast<double>(monotonic_ns() - t0) * 1e-9;
    const double cpu = cpu_seconds() - cpu0;
    pipeline.drain_latency(window);

    const LatencySummary latency = window.take();
    const PipelineTotals t = pipeline.totals();
    state.counters["frames"] = static_cast<double>(t.frames_in);
    state.counters["drops"] = static_cast<double>(t.frames_dropped);
    state.counters["not_ok"] = static_cast<double>(t.frames_processed - t.frames_ok);
    state.counters["p50_us"] = static_cast<double>(latency.p50_us);
    state.counters["p99_us"] = static_cast<double>(latency.p99_us);
    state.counters["max_us"] = static_cast<double>(latency.max_us);
    state.counters["cpu_%"] = 100.0 * cpu / wall;  // of one core
    state.counters["allocs"] = static_cast<double>(allocations);
    state.counters["fifo_threads"] = realtime.fifo_threads();
  }
}
BENCHMARK(BM_Pipeline800x600At60Fps)
    ->ArgNames({"s", "fifo"})
    ->Args({10, 0})
    ->Args({10, 50})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// One index through the ring and back, single thread: the bookkeeping cost per frame.
void BM_SpscRingPushPop(benchmark::State& state) {
  SpscRing<std::uint32_t> ring(8);
  std::uint32_t v = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ring.try_push(v));
    benchmark::DoNotOptimize(ring.try_pop(v));
  }
}
BENCHMARK(BM_SpscRingPushPop);

// Encoding and sending one lane message on the default udpm bus.
void BM_PublishLaneOnUdpm(benchmark::State& state) {
  LcmPublisher publisher(LcmConfig{});
  LaneEstimate e;
  e.ok = true;
  e.num_lines = 2;
  for (auto _ : state) {
    ++e.frame;
    benchmark::DoNotOptimize(publisher.publish_lane(e, 1, 2));
  }
}
BENCHMARK(BM_PublishLaneOnUdpm);

}  // namespace
}  // namespace ccdlane

BENCHMARK_MAIN();
