// Speed of lane-mark detection alone (the target: under 1 ms per 800x600 frame on one
// core, and per 1280x720 colour frame), of the whole per-frame estimate, and of
// rendering a synthetic frame (the daemon's demo pre-renders its frames at start-up).
// Frames are rendered once up front.
//   build/tests/bench/detection_bench --benchmark_min_time=2
#include <memory>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "app/config_loader.hpp"
#include "core/detection/lane_detector.hpp"
#include "core/lane/lane_estimator.hpp"
#include "core/synth/road_renderer.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/jpeg.hpp"
#include "tests/support/png_image.hpp"

namespace ccdlane {
namespace {

// The reference camera (800x600) and the Udacity one (1280x720, the configuration the
// real-picture tests use), 3 lanes, noise 1.
Config camera(int width) {
  if (width == 800) {
    Config c = default_config();
    c.attitude.theta_deg = 3.0;
    return c;
  }
  return load_config_file(std::string(CCDLANE_SOURCE_DIR) + "/tests/tools/data/udacity-advanced.toml");
}

struct Scene {
  Config config;
  std::vector<SynthFrame> truth;
  std::vector<std::vector<std::uint8_t>> pixels;
  std::vector<std::vector<std::uint8_t>> rgb;  // the same frames as rgb8 (grey colour)
  explicit Scene(int width, int frames = 16) : config(camera(width)) {
    SynthDrive drive(config.synth, config.nominal_pose());
    RoadRenderer renderer(config.camera, config.synth);
    for (int k = 0; k < frames; ++k) {
      truth.push_back(drive.frame(static_cast<std::uint64_t>(k) * 7));
      pixels.emplace_back(static_cast<std::size_t>(config.camera.Nu * config.camera.Nv));
      renderer.render(truth.back(), view(pixels.size() - 1));
      rgb.emplace_back(3 * pixels.back().size());
      for (std::size_t p = 0; p < pixels.back().size(); ++p)
        rgb.back()[3 * p] = rgb.back()[3 * p + 1] = rgb.back()[3 * p + 2] = pixels.back()[p];
    }
  }
  // Frame i in grey (colour = false) or as rgb8.
  ImageView frame(std::size_t i, bool colour) {
    if (!colour) return view(i);
    return {rgb[i].data(), config.camera.Nu, config.camera.Nv, 3 * config.camera.Nu, PixelFormat::rgb8, 8};
  }
  MutableImageView view(std::size_t i) {
    return {pixels[i].data(), config.camera.Nu, config.camera.Nv, config.camera.Nu, PixelFormat::mono8, 8};
  }
};

// Each rendered on first use only, so that one filtered benchmark (or a callgrind run
// of one) does not pay for rendering the other.
Scene& scene(int width) {
  if (width == 800) {
    static Scene s800(800);
    return s800;
  }
  static Scene s1280(1280);
  return s1280;
}

// Detection as the daemon runs it: the previous frame's lines as priors. Second
// argument: 0 grey (mono8), 1 colour (rgb8, the paint measure computed per scan row).
void BM_Detection(benchmark::State& state) {
  Scene& s = scene(static_cast<int>(state.range(0)));
  const bool colour = state.range(1) != 0;
  LaneDetector detector(s.config.camera, s.config.detection);
  std::vector<RoadLine> priors;
  for (int j = 0; j < s.truth[0].num_lines; ++j)
    priors.push_back({s.truth[0].y0_mm[static_cast<std::size_t>(j)], 0, 0});
  std::size_t i = 0;
  int lines = 0;
  for (auto _ : state) {
    const DetectionResult& r = detector.detect(s.frame(i, colour), s.truth[i].pose, priors);
    lines += r.num_lines;
    benchmark::DoNotOptimize(r.picks.data());
    i = (i + 1) % s.pixels.size();
  }
  state.counters["lines"] = benchmark::Counter(lines, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_Detection)->Args({800, 0})->Args({1280, 0})->Args({1280, 1})->Unit(benchmark::kMicrosecond);

// Detection with no prior: the first frame, or after a loss (the Hough vote on all marks).
void BM_DetectionCold(benchmark::State& state) {
  Scene& s = scene(static_cast<int>(state.range(0)));
  const bool colour = state.range(1) != 0;
  LaneDetector detector(s.config.camera, s.config.detection);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(detector.detect(s.frame(i, colour), s.truth[i].pose, {}).picks.data());
    i = (i + 1) % s.pixels.size();
  }
}
BENCHMARK(BM_DetectionCold)->Args({800, 0})->Args({1280, 0})->Args({1280, 1})->Unit(benchmark::kMicrosecond);

// The whole per-frame estimate: detect, solve (gyro priors), track, lane metrics.
void BM_Estimate(benchmark::State& state) {
  Scene& s = scene(static_cast<int>(state.range(0)));
  LaneEstimator estimator(s.config.estimator_options());
  std::size_t i = 0;
  int ok = 0;
  for (auto _ : state) {
    ok += estimator.estimate(s.view(i), i, s.truth[i].t_ns, s.truth[i].gyro).ok;
    i = (i + 1) % s.pixels.size();
  }
  state.counters["ok"] = benchmark::Counter(ok, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_Estimate)->Arg(800)->Arg(1280)->Unit(benchmark::kMicrosecond);

// Detection on the real 1280x720 pictures (texture, cars, hood), no prior.
void BM_DetectionRealPictures(benchmark::State& state) {
  const Config c = camera(1280);
  FrameDirectory dir(std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-advanced");
  std::vector<std::vector<std::uint8_t>> pixels(dir.size(), std::vector<std::uint8_t>(1280 * 720));
  for (std::size_t i = 0; i < dir.size(); ++i)
    dir.read(i, MutableImageView{pixels[i].data(), 1280, 720, 1280, PixelFormat::mono8, 8});
  LaneDetector detector(c.camera, c.detection);
  CameraPose pose = c.nominal_pose();
  pose.attitude.theta = deg_to_rad(-1.5);  // as the solver finds it
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        detector.detect(ImageView{pixels[i].data(), 1280, 720, 1280, PixelFormat::mono8, 8}, pose, {}).picks.data());
    i = (i + 1) % pixels.size();
  }
}
BENCHMARK(BM_DetectionRealPictures)->Unit(benchmark::kMicrosecond);

// The same two pictures in colour (tests/data/real), no prior.
void BM_DetectionRealColourPictures(benchmark::State& state) {
  const Config c = camera(1280);
  std::vector<test::PngImage> frames;
  for (const char* name : {"000000.png", "000001.png"})
    frames.push_back(
        test::read_png(std::string(CCDLANE_SOURCE_DIR) + "/tests/data/real/udacity-advanced-colour/" + name));
  LaneDetector detector(c.camera, c.detection);
  const CameraPose pose = c.nominal_pose();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(detector.detect(frames[i].view(), pose, {}).picks.data());
    i = (i + 1) % frames.size();
  }
}
BENCHMARK(BM_DetectionRealColourPictures)->Unit(benchmark::kMicrosecond);

// Real freeway stills in colour (the ten TuSimple pictures of tests/data/real/tusimple:
// pale concrete, Botts' dots, trucks), with their nominal camera.
struct TuSimpleStills {
  Config config;
  std::vector<std::vector<std::uint8_t>> pixels;

  TuSimpleStills() : config(load_config_file(std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple/camera.toml")) {
    JpegReader reader;
    for (int k = 0; k < 10; ++k) {
      pixels.emplace_back(static_cast<std::size_t>(1280 * 720 * 3));
      const std::string path = std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple/images/000" + std::to_string(k) + ".jpg";
      if (reader.read(path.c_str(), view(static_cast<std::size_t>(k))) != PgmFault::none) pixels.pop_back();
    }
  }
  MutableImageView view(std::size_t i) { return {pixels[i].data(), 1280, 720, 1280 * 3, PixelFormat::rgb8, 8}; }
};

// Detection on them from the pose the solver finds for them (pitch about 7 degrees), no
// prior: a tracking frame's cost on concrete with dots.
void BM_DetectionTuSimpleStills(benchmark::State& state) {
  TuSimpleStills s;
  LaneDetector detector(s.config.camera, s.config.detection);
  CameraPose pose = s.config.nominal_pose();
  pose.attitude.theta = deg_to_rad(7.3);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(detector.detect(s.view(i), pose, {}).picks.data());
    i = (i + 1) % s.pixels.size();
  }
}
BENCHMARK(BM_DetectionTuSimpleStills)->Unit(benchmark::kMicrosecond);

// The stills held: each still has its own estimator, which sees the same picture again
// and again, as a drive's next frame from the pose it solved. Timing starts after
// kWarmUpFrames frames (the mount's height settles after a second); the stills kept are
// those whose warm-up estimates `keep` takes (it sees each one's ok and state in order).
struct HeldStills {
  static constexpr std::uint64_t kWarmUpFrames = 60;
  TuSimpleStills s;
  std::vector<std::unique_ptr<LaneEstimator>> estimators;
  std::vector<std::size_t> stills;
  std::uint64_t frame = kWarmUpFrames;
  std::size_t next = 0;

  template <typename Keep>
  explicit HeldStills(Keep keep) {
    for (std::size_t i = 0; i < s.pixels.size(); ++i) {
      auto estimator = std::make_unique<LaneEstimator>(s.config.estimator_options());
      std::vector<std::pair<bool, EstimatorState>> warm_up;
      for (std::uint64_t f = 0; f < kWarmUpFrames; ++f) {
        const LaneEstimate& e =
            estimator->estimate(s.view(i), f, static_cast<std::int64_t>(f) * 40000000, std::nullopt);
        warm_up.emplace_back(e.ok, e.state);
      }
      if (!keep(warm_up)) continue;
      estimators.push_back(std::move(estimator));
      stills.push_back(i);
    }
  }
  // The next still's next frame, the stills in turn.
  const LaneEstimate& estimate_next() {
    const std::int64_t t_ns = static_cast<std::int64_t>(frame) * 40000000;
    const LaneEstimate& e = estimators[next]->estimate(s.view(stills[next]), frame, t_ns, std::nullopt);
    if (++next == stills.size()) {
      next = 0;
      ++frame;
    }
    return e;
  }
};

// The whole estimate of a tracking frame on those stills (detection, solve, lines and
// the warning's filter), on the stills whose lane was tracked through the last 20 frames
// of the warm-up: a lost lane's frames are timed below. The per-frame budget (1 ms) is this.
void BM_EstimateTuSimpleTracking(benchmark::State& state) {
  HeldStills held([](const std::vector<std::pair<bool, EstimatorState>>& warm_up) {
    constexpr std::size_t kTrackedFrames = 20;
    for (std::size_t f = warm_up.size() - kTrackedFrames; f < warm_up.size(); ++f)
      if (!warm_up[f].first || warm_up[f].second != EstimatorState::tracking) return false;
    return true;
  });
  if (held.stills.empty()) {
    state.SkipWithError("no still is tracked");
    return;
  }
  std::int64_t tracked = 0;
  for (auto _ : state) {
    const LaneEstimate& e = held.estimate_next();
    tracked += e.ok && e.state == EstimatorState::tracking;
  }
  state.counters["stills"] = static_cast<double>(held.stills.size());
  state.counters["tracked"] = benchmark::Counter(static_cast<double>(tracked), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_EstimateTuSimpleTracking)->Unit(benchmark::kMicrosecond);

// The whole estimate on the stills whose lane the track does not keep (a tracked frame
// without a lane in the warm-up): each frame as it comes, a tracked one without a lane
// looking again afresh (four detections where it costs one), a search after a second of
// them. What a lost lane costs frame by frame until it is found again; `searching` is the
// share of the frames timed that searched (or took the look again's lane).
void BM_EstimateTuSimpleLostTrack(benchmark::State& state) {
  HeldStills held([](const std::vector<std::pair<bool, EstimatorState>>& warm_up) {
    for (const auto& [ok, state_of] : warm_up)
      if (!ok && state_of == EstimatorState::tracking) return true;
    return false;
  });
  if (held.stills.empty()) {
    state.SkipWithError("every still's lane is tracked");
    return;
  }
  int searching = 0;
  for (auto _ : state) searching += held.estimate_next().state == EstimatorState::searching;
  state.counters["stills"] = static_cast<double>(held.stills.size());
  state.counters["searching"] = benchmark::Counter(searching, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_EstimateTuSimpleLostTrack)->Unit(benchmark::kMicrosecond);

// The whole estimate of each still alone (replay --stills): a search, which detects and
// solves from up to 50 starting poses (without a gyro; 10 with one); what a lost lane costs.
void BM_EstimateTuSimpleStillSearch(benchmark::State& state) {
  TuSimpleStills s;
  LaneEstimator estimator(s.config.estimator_options());
  std::size_t i = 0;
  int ok = 0;
  for (auto _ : state) {
    estimator.reset();
    ok += estimator.estimate(s.view(i), i, static_cast<std::int64_t>(i) * 1000000000, std::nullopt).ok;
    i = (i + 1) % s.pixels.size();
  }
  state.counters["ok"] = benchmark::Counter(ok, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_EstimateTuSimpleStillSearch)->Unit(benchmark::kMillisecond);

void BM_RenderSyntheticFrame(benchmark::State& state) {
  const Config c = camera(static_cast<int>(state.range(0)));
  SynthDrive drive(c.synth, c.nominal_pose());
  RoadRenderer renderer(c.camera, c.synth);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(c.camera.Nu * c.camera.Nv));
  const MutableImageView view{px.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8};
  std::uint64_t k = 0;
  for (auto _ : state) {
    renderer.render(drive.frame(k++), view);
    benchmark::DoNotOptimize(px.data());
  }
}
BENCHMARK(BM_RenderSyntheticFrame)->Arg(800)->Arg(1280)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ccdlane

BENCHMARK_MAIN();
