// Which marks a line's gap near the car lends it: raised markers found beside their own
// shadow, in no line, below the line's nearest pick and within the window of its
// extension; nothing else.
#include "core/lane/gap_markers.hpp"

#include <array>
#include <vector>

#include <gtest/gtest.h>

#include "app/config.hpp"

namespace ccdlane {
namespace {

class GapMarkers : public ::testing::Test {
 protected:
  GapMarkers() : config_(default_config()), camera_(config_.camera, config_.nominal_pose()) {
    // The line's picks: its paint from 10 to 20 m.
    for (double x = 10000.0; x <= 20000.0; x += 1000.0) {
      const Vec2 p = pixel(x, 0.0);
      picks_.push_back(Pick{kLine, p.x(), p.y()});
    }
  }
  // Where the line's point `x` mm ahead, moved `across_px` pixels to the right, is seen.
  Vec2 pixel(double x, double across_px) const {
    const auto p = camera_.pixel_from_point(Vec3(x, line_.y_at(x), 0.0));
    EXPECT_TRUE(p);
    return *p + Vec2(across_px, 0.0);
  }
  // A marker lit beside its shadow seen there; `line` is the detection line it joined.
  MarkCandidate marker(double x, double across_px, int line = -1) const {
    const Vec2 p = pixel(x, across_px);
    MarkCandidate m;
    m.left_px = p.x() - 2.0;
    m.right_px = p.x() + 2.0;
    m.py = p.y();
    m.dot = true;
    m.shadow_side = +1;
    m.shadow_px = 3.0f;
    m.line = static_cast<std::int16_t>(line);
    return m;
  }

  static constexpr int kLine = 1;
  Config config_;
  CameraModel camera_;
  RoadLine line_{-1800.0, 0.0, 0.0};
  std::vector<Pick> picks_;
};

TEST_F(GapMarkers, OnlyMarkersInTheGapNearTheLinesExtensionAreLent) {
  std::vector<MarkCandidate> marks;
  marks.push_back(marker(6000.0, 0.0));     // on the extension, in the gap: lent
  marks.push_back(marker(7000.0, 20.0));    // 20 px beside it: lent
  marks.push_back(marker(6000.0, 40.0));    // 40 px beside it: another line's, or none
  marks.push_back(marker(15000.0, 0.0));    // among the line's picks, not below them
  marks.push_back(marker(8000.0, 0.0, 0));  // taken by a line already
  MarkCandidate plain = marker(5000.0, 0.0);
  plain.shadow_side = 0;  // a dot without its shadow: on asphalt, a speck
  marks.push_back(plain);
  MarkCandidate joint = marker(5500.0, 0.0);
  joint.joint = true;
  marks.push_back(joint);

  std::array<Pick, 8> out{};
  ASSERT_EQ(gap_markers(marks, picks_, camera_, line_, kLine, out), 2);
  EXPECT_EQ(out[0].line, kLine);
  EXPECT_DOUBLE_EQ(out[0].px, marks[0].px());
  EXPECT_DOUBLE_EQ(out[0].py, marks[0].py);
  EXPECT_EQ(out[1].line, kLine);
  EXPECT_DOUBLE_EQ(out[1].px, marks[1].px());

  // As far as `out` has room; and a line with no picks has no gap.
  std::array<Pick, 1> one{};
  EXPECT_EQ(gap_markers(marks, picks_, camera_, line_, kLine, one), 1);
  EXPECT_EQ(gap_markers(marks, picks_, camera_, line_, kLine + 1, out), 0);
}

// The window is in pixels at the marker's own distance, not in millimetres: a marker 100
// mm beside the line is lent where that is 20 px (farther) and not where it is 30 px.
TEST_F(GapMarkers, TheWindowIsThePicturesAtTheMarkersDistance) {
  const double mm_per_px_per_mm = config_.camera.pitch_u() / config_.nominal_pose().f_mm;
  for (const double px : {20.0, 30.0}) {
    const double x = 100.0 / (px * mm_per_px_per_mm);  // where 100 mm is `px` pixels
    ASSERT_LT(x, 10000.0) << "below the line's nearest pick";
    const std::vector<MarkCandidate> marks{marker(x, px)};
    std::array<Pick, 2> out{};
    EXPECT_EQ(gap_markers(marks, picks_, camera_, line_, kLine, out), px <= kGapMarkerWindowPx ? 1 : 0)
        << x << " mm ahead, " << px << " px";
  }
}

}  // namespace
}  // namespace ccdlane
