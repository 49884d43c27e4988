// Detection on rendered colour frames with the disturbances of real roads, against the
// truth projection: a yellow edge line on concrete (nearly invisible in grey), hard tree
// shadows across the lane, a concrete barrier with a bright foot beside the road. Every
// road line must be found at its true position, and nothing else reported.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/lane_detector.hpp"
#include "tests/core/detection/detection_truth.hpp"
#include "tests/core/synth/rendered_road.hpp"

namespace ccdlane {
namespace {

// The pick bounds of the clean grey scene (lane_detector_test: sensor noise sigma 1 grey
// level at mark contrasts of 60+ levels gives picks of ~0.1 px rms); a disturbance that
// pulled picks off the paint would break them.
constexpr double kPickRmsPx = 0.15;
constexpr double kPickWorstPx = 0.8;
// A detected line farther than this from every truth line (at the true pose) is not on
// paint: a barrier foot (700 mm beyond the edge line) or a shadow border.
constexpr double kOnPaintMm = 100.0;
// Under hard shadows one kind of pick is off by more: where a shadow border runs along
// the paint at a small angle, only the sunlit part of the mark stands out as a bar (the
// shaded part is paint too, at the shaded road's contrast), and the bar's centre is off
// by up to half the shaded part. Seen: 1.0 px on a near mark 16 px wide. Such picks must
// still lie well on the paint; 2 px is an eighth of such a mark. Not derived from the
// noise: it is the known limit of a detector that takes the brightest bar (see report).
constexpr double kShadowPickWorstPx = 2.0;

Config colour_highway() {
  Config c = default_config();
  c.attitude = {0.0, 3.0, 0.0};
  c.synth.colour = true;
  return c;
}

// Every truth line visible between 5 and 40 m found once, in order, at its place, its
// picks on the paint; returns the worst pick rms.
double expect_every_line_and_nothing_else(const Config& c, std::uint64_t k, const char* scene,
                                          double worst_px = kPickWorstPx) {
  test::RenderedRoad road(c, PixelFormat::rgb8);
  LaneDetector det(c.camera, c.detection);
  const SynthFrame f = road.render(k);
  const DetectionResult& r = det.detect(road.view, f.pose, {});
  EXPECT_EQ(r.num_lines, f.num_lines) << scene << " frame " << k;
  const std::vector<int> truth = test::match(r, f);
  for (int j = 0; j < r.num_lines; ++j) {
    const int t = truth[static_cast<std::size_t>(j)];
    EXPECT_EQ(t, j) << scene << " frame " << k << ": left to right, each line once";
    EXPECT_NEAR(r.lines[j].fit.y0_mm, f.y0_mm[static_cast<std::size_t>(t)], kOnPaintMm)
        << scene << " frame " << k << " line " << j;
  }
  const test::PickErrors e = test::pick_errors(r, f, CameraModel(c.camera, f.pose), truth);
  EXPECT_GT(e.n, 25 * f.num_lines) << scene << " frame " << k;
  EXPECT_LT(e.rms, kPickRmsPx) << scene << " frame " << k;
  EXPECT_LT(e.worst, worst_px) << scene << " frame " << k;
  return e.rms;
}

TEST(LaneDetectorRealRoad, YellowEdgeLineOnConcrete) {
  Config c = colour_highway();
  c.synth.yellow_left_edge = true;
  c.synth.surface = RoadSurface::concrete;
  double worst = 0;
  for (std::uint64_t k : {0u, 17u, 45u}) worst = std::max(worst, expect_every_line_and_nothing_else(c, k, "concrete"));
  RecordProperty("worst_pick_rms_px", std::to_string(worst));

  // The same frame in grey: the yellow line's luma is the concrete's, so it is not found
  // there. Colour is what finds it.
  test::RenderedRoad grey(c, PixelFormat::mono8);
  LaneDetector det(c.camera, c.detection);
  const SynthFrame f = grey.render(0);
  const DetectionResult& r = det.detect(grey.view, f.pose, {});
  for (int j = 0; j < r.num_lines; ++j) EXPECT_GT(std::abs(r.lines[j].fit.y0_mm - f.y0_mm[0]), 500.0);
}

TEST(LaneDetectorRealRoad, HardShadowsAcrossTheLane) {
  Config c = colour_highway();
  c.synth.hard_shadows = true;
  c.synth.shadow_depth = 0.55;
  double worst = 0;
  for (std::uint64_t k : {0u, 9u, 23u, 38u, 61u})
    worst = std::max(worst, expect_every_line_and_nothing_else(c, k, "shadows", kShadowPickWorstPx));
  RecordProperty("worst_pick_rms_px", std::to_string(worst));
}

TEST(LaneDetectorRealRoad, BarrierWithABrightFootBesideTheRoad) {
  for (RoadSurface surface : {RoadSurface::asphalt, RoadSurface::concrete}) {
    Config c = colour_highway();
    c.synth.barrier = true;
    c.synth.yellow_left_edge = true;
    c.synth.surface = surface;
    // Two lanes, the own one next to the barrier: the foot is near, in view at mark-like
    // widths, and every line is in view.
    c.synth.lanes = 2;
    c.synth.ego_lane = 0;
    double worst = 0;
    for (std::uint64_t k : {0u, 30u, 55u}) worst = std::max(worst, expect_every_line_and_nothing_else(c, k, "barrier"));
    RecordProperty(surface == RoadSurface::asphalt ? "asphalt_worst_pick_rms_px" : "concrete_worst_pick_rms_px",
                   std::to_string(worst));
  }
}

TEST(LaneDetectorRealRoad, EverythingAtOnce) {
  Config c = colour_highway();
  c.synth.yellow_left_edge = c.synth.hard_shadows = c.synth.barrier = true;
  c.synth.surface = RoadSurface::concrete;
  c.synth.shadow_depth = 0.55;
  c.synth.lanes = 2;
  c.synth.ego_lane = 0;
  for (std::uint64_t k : {4u, 33u}) expect_every_line_and_nothing_else(c, k, "all", kShadowPickWorstPx);
}

}  // namespace
}  // namespace ccdlane
