// No lane in noise: sequences of pure-noise frames (grey and colour; uniform, Gaussian,
// salt and pepper, bright blobs, bright bars; weak to strong) through one estimator, as
// replay and the daemon run it, must give no ok frame and no departure or warning. The
// truth is that these pictures hold no lane at all; one ok frame is a failure.
#include <cstdlib>
#include <optional>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include "core/lane/lane_estimator.hpp"
#include "tests/core/lane/noise_frames.hpp"
#include "tests/core/synth/rendered_road.hpp"

namespace ccdlane {
namespace {

// Frames per run: CCDLANE_NOISE_FRAMES overrides (the 10,000 are run so by hand,
// README "Soak"), the default keeps the test a few seconds long.
int frame_count() {
  if (const char* s = std::getenv("CCDLANE_NOISE_FRAMES")) return std::max(1, std::atoi(s));
  return 2000;
}

// CCDLANE_NOISE_SEED is added to each run's seed: noise the checks were not designed on.
std::uint64_t seed_offset() {
  const char* s = std::getenv("CCDLANE_NOISE_SEED");
  return s ? std::strtoull(s, nullptr, 10) : 0;
}

struct NoiseTally {
  int frames = 0, ok = 0, departures = 0, warnings = 0;
  std::string first_ok;  // what the first ok frame was, for the failure message
};

// `frames` noise frames cycling through every texture and strength, one estimator over
// the whole sequence (its tracker and lane filter carry over, as in a drive).
NoiseTally run_noise(const Config& c, PixelFormat format, int frames, std::uint64_t seed, bool with_gyro = true,
                     std::span<const test::NoiseTexture> textures = test::kNoiseTextures,
                     std::optional<double> speed_mps = 25.0) {
  test::NoiseFrames noise(c.camera.Nu, c.camera.Nv, format, seed + seed_offset());
  LaneEstimator est(c.estimator_options());
  const Attitude nominal = c.nominal_pose().attitude;
  const Gx1Angles gyro{rad_to_deg(nominal.phi), -rad_to_deg(nominal.theta), 0.0};
  VehicleInputs vehicle;
  vehicle.speed_mps = speed_mps;
  NoiseTally tally;
  constexpr int kLevels = 5;
  for (int k = 0; k < frames; ++k) {
    const test::NoiseTexture texture = textures[static_cast<std::size_t>(k) % textures.size()];
    const double level = static_cast<double>((k / 5) % kLevels) / (kLevels - 1);
    const ImageView& image = noise.render(texture, level);
    // Half the frames with the gyro's reading, half without (a recording without one).
    const std::optional<Gx1Angles> g = with_gyro && (k / 50) % 2 == 0 ? std::optional<Gx1Angles>(gyro) : std::nullopt;
    const LaneEstimate& e = est.estimate(image, static_cast<std::uint64_t>(k), k * 33'333'333LL, g, vehicle);
    ++tally.frames;
    if (e.ok && tally.ok++ == 0)
      tally.first_ok = "frame " + std::to_string(k) + " (" + test::to_string(texture) + ", level " +
                       std::to_string(level) + "): " + std::to_string(e.num_lines) + " lines, width " +
                       std::to_string(e.lane_width_mm) + " mm, rms " + std::to_string(e.rms_px) + " px, curvature " +
                       std::to_string(e.curvature_per_m) + " /m, heading " + std::to_string(e.heading_deg) + " deg";
    tally.departures += e.departure != Departure::none;
    tally.warnings += e.ldw.fired != ldw::Side::none;
  }
  return tally;
}

TEST(LaneEstimatorNoise, NoLaneInGreyNoise) {
  const Config c = default_config();  // the reference camera, 800x600, as the issue ran it
  const NoiseTally t = run_noise(c, PixelFormat::mono8, frame_count(), 17);
  EXPECT_EQ(t.ok, 0) << t.ok << " of " << t.frames << " noise frames ok; the first: " << t.first_ok;
  EXPECT_EQ(t.departures, 0);
  EXPECT_EQ(t.warnings, 0);
}

// Dark pictures are where the contrast threshold is lowered (contrast_threshold.hpp):
// faint bars on a dark, noisy grey make no lane either.
TEST(LaneEstimatorNoise, NoLaneInDarkNoise) {
  const Config c = default_config();
  constexpr test::NoiseTexture kDark[] = {test::NoiseTexture::dark_bars};
  const NoiseTally t = run_noise(c, PixelFormat::mono8, frame_count() / 4, 41, true, kDark);
  EXPECT_EQ(t.ok, 0) << t.ok << " of " << t.frames << " noise frames ok; the first: " << t.first_ok;
  EXPECT_EQ(t.departures, 0);
  EXPECT_EQ(t.warnings, 0);
}

TEST(LaneEstimatorNoise, NoLaneInColourNoise) {
  const Config c = default_config();
  const NoiseTally t = run_noise(c, PixelFormat::rgb8, frame_count() / 4, 29);
  EXPECT_EQ(t.ok, 0) << t.ok << " of " << t.frames << " noise frames ok; the first: " << t.first_ok;
  EXPECT_EQ(t.departures, 0);
  EXPECT_EQ(t.warnings, 0);
}

// Without a gyro but with a lane-width prior the roll is observable and every solve is
// full rank: only the support checks stand between noise and a lane. Seed 53 as well:
// its frame 109 (an 11 px bar and one thin far mark of something else, which a
// least-squares width slope took for paint) was a lane until paint_width_slope.
TEST(LaneEstimatorNoise, NoLaneInNoiseWithALaneWidthPriorAndNoGyro) {
  Config c = default_config();
  c.prior.lane_width_mm = Prior{3600.0, 300.0};
  for (const std::uint64_t seed : {41, 53}) {
    const NoiseTally t = run_noise(c, PixelFormat::mono8, frame_count() / 4, seed, false);
    EXPECT_EQ(t.ok, 0) << "seed " << seed << ": " << t.ok << " of " << t.frames
                       << " noise frames ok; the first: " << t.first_ok;
    EXPECT_EQ(t.departures, 0);
    EXPECT_EQ(t.warnings, 0);
  }
}

// A video replayed, or a daemon without a gateway, has no speed: a lane's bend is then
// judged at the speed a car takes it at (judged_speed_mps), down to 36 km/h, where the
// configured 72 km/h would refuse it.
TEST(LaneEstimatorNoise, NoLaneInNoiseWithoutASpeed) {
  const Config c = default_config();
  const NoiseTally t =
      run_noise(c, PixelFormat::mono8, frame_count() / 4, 53, true, test::kNoiseTextures, std::nullopt);
  EXPECT_EQ(t.ok, 0) << t.ok << " of " << t.frames << " noise frames ok; the first: " << t.first_ok;
  EXPECT_EQ(t.departures, 0);
  EXPECT_EQ(t.warnings, 0);
}

// The same test must see a lane where there is one: the noise runs above are not passing
// merely because nothing ever is ok. A real drive with the same camera and options.
TEST(LaneEstimatorNoise, TheSameEstimatorFindsTheLaneOnARoad) {
  Config c = default_config();
  test::RenderedRoad d(c);
  LaneEstimator est(c.estimator_options());
  Config width_prior = c;  // and as the no-gyro noise run has it
  width_prior.prior.lane_width_mm = Prior{3600.0, 300.0};
  LaneEstimator no_gyro(width_prior.estimator_options());
  int ok = 0, ok_without_gyro = 0;
  for (std::uint64_t k = 0; k < 20; ++k) {
    const SynthFrame f = d.render(k);
    ok += est.estimate(d.view, k, f.t_ns, f.gyro).ok;
    ok_without_gyro += no_gyro.estimate(d.view, k, f.t_ns, std::nullopt).ok;
  }
  EXPECT_EQ(ok, 20);
  EXPECT_EQ(ok_without_gyro, 20);
}

}  // namespace
}  // namespace ccdlane
