// Scoring rules on hand-made lanes: mask centres per row, hits exactly up to the
// width-scaled threshold, the 85 % rules for found lanes and false lines.
#include "tools/ccdlane/lane_score.hpp"

#include <gtest/gtest.h>

#include "app/config.hpp"
#include "tools/ccdlane/road_line_picture.hpp"

namespace ccdlane::cli {
namespace {

TEST(LaneScore, MaskLanesAreTheCentresOfEachGreyLevelPerRow) {
  std::vector<std::uint8_t> mask(10 * 3, 0);
  mask[0 * 10 + 2] = mask[0 * 10 + 3] = 5;  // row 1: level 5 on columns 3 and 4
  mask[2 * 10 + 7] = 9;                     // row 3: level 9 on column 8
  mask[2 * 10 + 1] = 5;                     // row 3: level 5 on column 2
  const auto lanes = lanes_of_mask(ImageView{mask.data(), 10, 3, 10, PixelFormat::mono8, 8});
  ASSERT_EQ(lanes.size(), 2u);
  EXPECT_EQ(lanes[0].level, 5);
  ASSERT_EQ(lanes[0].points.size(), 2u);
  EXPECT_EQ(lanes[0].points[0], Vec2(3.5, 1));
  EXPECT_EQ(lanes[0].points[1], Vec2(2, 3));
  EXPECT_EQ(lanes[1].level, 9);
  EXPECT_EQ(lanes[1].points[0], Vec2(8, 3));
}

// A lane annotated as the projection of `line` shifted by `dx` pixels on rows first..last.
AnnotatedLane lane_along(const CameraModel& cam, const RoadLine& line, double dx, int first, int last) {
  AnnotatedLane lane;
  lane.level = 1;
  for (int row = first; row <= last; ++row)
    if (const auto x = road_line_column_at_row(cam, line, row, 500, 300000)) lane.points.emplace_back(*x + dx, row);
  return lane;
}

TEST(LaneScore, HitsUpToTheThresholdScaledByWidth) {
  const Config c = default_config();
  const CameraModel cam(c.camera, c.nominal_pose());
  const RoadLine line{-1800, 0.01, 1e-7};
  const double threshold = ScoreRules::threshold_for_width(20.0, c.camera.Nu);
  for (const double dx : {0.0, threshold - 0.01, -(threshold - 0.01)}) {
    const AnnotatedLane lane = lane_along(cam, line, dx, 400, 580);
    ASSERT_GT(lane.points.size(), 150u);
    const FrameScore s = score_frame({&lane, 1}, c.camera.Nu, cam, {&line, 1});
    EXPECT_EQ(s.found, 1) << dx;
    EXPECT_EQ(s.false_lines, 0) << dx;
    EXPECT_EQ(s.hit_points, s.points) << dx;
  }
  const AnnotatedLane off = lane_along(cam, line, threshold + 0.01, 400, 580);
  const FrameScore s = score_frame({&off, 1}, c.camera.Nu, cam, {&line, 1});
  EXPECT_EQ(s.found, 0);
  EXPECT_EQ(s.hit_points, 0u);
  EXPECT_EQ(s.false_lines, 1);
  EXPECT_EQ(s.reported, 1);
}

TEST(LaneScore, EightyFivePercentRules) {
  const Config c = default_config();
  const CameraModel cam(c.camera, c.nominal_pose());
  const RoadLine line{1800, 0.0, 0.0};
  // 100 rows on the line, then rows off it: 85 of 100 hit is found, 84 is not.
  for (const int on : {85, 84}) {
    AnnotatedLane lane = lane_along(cam, line, 0.0, 401, 400 + on);
    const AnnotatedLane off = lane_along(cam, line, 50.0, 401 + on, 500);
    lane.points.insert(lane.points.end(), off.points.begin(), off.points.end());
    ASSERT_EQ(lane.points.size(), 100u);
    const FrameScore s = score_frame({&lane, 1}, c.camera.Nu, cam, {&line, 1});
    EXPECT_EQ(s.found, on >= 85 ? 1 : 0) << on;
    EXPECT_EQ(s.false_lines, on >= 85 ? 0 : 1) << on;
    EXPECT_EQ(s.hit_points, static_cast<std::size_t>(on));
  }
  // No line reported: nothing found, nothing false.
  const AnnotatedLane lane = lane_along(cam, line, 0.0, 400, 500);
  const FrameScore none = score_frame({&lane, 1}, c.camera.Nu, cam, {});
  EXPECT_EQ(none.found, 0);
  EXPECT_EQ(none.reported, 0);
  EXPECT_EQ(none.false_lines, 0);
}

}  // namespace
}  // namespace ccdlane::cli
