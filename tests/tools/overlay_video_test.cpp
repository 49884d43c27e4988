// The annotated video: its strip's text (the radius rule of the monitor), and the video
// itself: one frame per frame drawn, at the times given, with the lane filled and a
// warning drawn on its side.
#include "tools/ccdlane/overlay_video.hpp"

#include <gtest/gtest.h>

#include "base/image_buffer.hpp"
#include "drivers/frames/video_reader.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane::cli {
namespace {

LaneEstimate ok_estimate() {
  LaneEstimate e;
  e.ok = true;
  e.lane_width_mm = 3660.0;
  e.lateral_offset_mm = 120.0;
  e.heading_deg = -1.26;
  e.curvature_per_m = 1.0 / 850.0;
  e.ldw.available = true;
  e.ldw.reason = ldw::Availability::none;
  e.ldw.track = ldw::TrackStatus::tracking;
  return e;
}

TEST(OverlayStripText, SaysTheLaneAndTheRadiusOnlyUnderTenKilometres) {
  LaneEstimate e = ok_estimate();
  EXPECT_EQ(overlay_strip_text(e),
            "width 3.66 m | offset +0.12 m | heading -1.3 deg | radius 850 m | ok, tracking | LDW available");
  e.curvature_per_m = 1.0 / 885'327.0;
  EXPECT_NE(overlay_strip_text(e).find("radius straight |"), std::string::npos);
  e.curvature_per_m = 0.0;
  EXPECT_NE(overlay_strip_text(e).find("radius straight |"), std::string::npos);
  e.ok = false;
  e.reason = EstimateFailure::no_lane;
  e.ldw.available = false;
  e.ldw.reason = ldw::Availability::no_lane;
  e.ldw.track = ldw::TrackStatus::coasting;
  EXPECT_EQ(overlay_strip_text(e),
            "width - | offset - | heading - | radius - | no_lane, coasting | LDW unavailable (no_lane)");
}

TEST(OverlayVideo, OneFramePerFrameAtItsTimeWithTheWarningOnItsSide) {
  test::TempDir dir;
  const Config config = default_config();
  LaneEstimator estimator(config.estimator_options());
  const ImageBuffer grey(800, 600, PixelFormat::mono8, 8);
  (void)estimator.estimate(grey.view(), 0, 0, std::nullopt);  // a blank frame: nothing found
  OverlayVideo video(dir.file("o.mp4"), 800, 600, 1, 1000);
  for (int k = 0; k < 4; ++k) {
    LaneEstimate e = ok_estimate();
    e.t_ns = k * 50'000'000LL;
    e.ldw.warning = k == 2 ? ldw::Side::right : ldw::Side::none;
    video.add(grey.view(), e, estimator, config);
  }
  video.finish();
  VideoReader r(dir.file("o.mp4"));
  const ImageBuffer frame(800, 600, PixelFormat::rgb8, 8);
  std::int64_t t = 0;
  for (int k = 0; k < 4; ++k) {
    ASSERT_EQ(r.next(frame.view(), t), VideoRead::frame) << k;
    EXPECT_EQ(t, k * 50'000'000LL);
    // The right edge's bar is red only while the warning is held.
    const std::uint8_t* edge = frame.view().row(300) + 3 * 795;
    EXPECT_EQ(edge[0] > 200 && edge[1] < 90, k == 2) << k << ": " << int{edge[0]} << "," << int{edge[1]};
    // The strip is black at the bottom.
    EXPECT_LT(frame.view().row(598)[3 * 790], 40);
  }
  EXPECT_EQ(r.next(frame.view(), t), VideoRead::end);
}

}  // namespace
}  // namespace ccdlane::cli
