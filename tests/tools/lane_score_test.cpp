// Scoring rules on hand-made lanes: mask centres per row, hits exactly up to the
// width-scaled threshold, the 85 % rules for found lanes and false lines, and TuSimple's
// own benchmark.
#include "tools/ccdlane/lane_score.hpp"

#include <vector>

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

// Per lane, the line that hits most of its points and how far it passes each: a lane 7 px
// right of the second of two lines reads line 1 and -7 px on every row (the line is left
// of it); a lane no line comes near reads no line and no offsets.
TEST(LaneScore, EachLaneSaysWhichLineHitsItAndByHowMuchItMisses) {
  const Config c = default_config();
  const CameraModel cam(c.camera, c.nominal_pose());
  const RoadLine lines[] = {{1800, 0.0, 0.0}, {-1800, 0.0, 0.0}};
  const AnnotatedLane lanes[] = {lane_along(cam, lines[1], 7.0, 420, 560),
                                 lane_along(cam, {-9000, 0.0, 0.0}, 0.0, 430, 440)};
  ASSERT_GT(lanes[0].points.size(), 100u);
  LanePointHits hits;
  score_frame(lanes, c.camera.Nu, cam, lines, {}, &hits);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[0].line, 1);
  ASSERT_EQ(hits[0].offset_px.size(), lanes[0].points.size());
  ASSERT_EQ(hits[0].hit.size(), lanes[0].points.size());
  for (std::size_t p = 0; p < lanes[0].points.size(); ++p) {
    ASSERT_TRUE(hits[0].offset_px[p]) << p;
    EXPECT_NEAR(*hits[0].offset_px[p], -7.0, 1e-6) << p;
    EXPECT_TRUE(hits[0].hit[p]) << p;
  }
  EXPECT_EQ(hits[1].line, -1);
  ASSERT_EQ(hits[1].offset_px.size(), lanes[1].points.size());
  for (std::size_t p = 0; p < lanes[1].points.size(); ++p) {
    EXPECT_FALSE(hits[1].offset_px[p]);
    EXPECT_FALSE(hits[1].hit[p]);
  }
}

// TuSimple's own benchmark (lane.py's LaneEval.bench) on hand-made lanes: every sampled
// row counts, a row where neither lane nor line has a point is a hit, a line's point where
// the lane has none is a miss; lanes without a match are FN, lines matching no lane FP;
// too many lines score 0, 0, 1; beyond four lanes the worst lane and one FN are forgiven.
TEST(LaneScore, TuSimplesLaneEvalCountsEverySampledRow) {
  const Config c = default_config();
  const CameraModel cam(c.camera, c.nominal_pose());
  const RoadLine a{-1800, 0.01, 1e-7}, b{1800, 0.01, 1e-7}, far_off{-4000, 0.01, 1e-7};
  // Row 5 is above the horizon: no line has a point there.
  std::vector<double> rows{5};
  for (int r = 400; r < 500; r += 10) rows.push_back(r);
  for (const RoadLine& l : {a, b, far_off}) {
    ASSERT_FALSE(road_line_column_at_row(cam, l, 5, 500, 300000));
    for (std::size_t k = 1; k < rows.size(); ++k) ASSERT_TRUE(road_line_column_at_row(cam, l, rows[k], 500, 300000));
  }
  const AnnotatedLane lane_a = lane_along(cam, a, 0.0, 400, 490);
  AnnotatedLane lane_b;  // labelled on its first five sampled rows only
  for (const Vec2& p : lane_along(cam, b, 0.0, 400, 440).points)
    if (static_cast<int>(p.y()) % 10 == 0) lane_b.points.push_back(p);
  const std::vector<AnnotatedLane> lanes{lane_a, lane_b};
  const std::vector<RoadLine> lines{a, b, far_off};
  const LaneEvalScore s = lane_eval_frame(lanes, rows, c.camera.Nu, cam, lines);
  // Lane a: 11 of 11 rows. Lane b: row 5 and its five rows hit, the line's five points
  // below them miss: 6 of 11, no match.
  EXPECT_NEAR(s.accuracy, (1.0 + 6.0 / 11.0) / 2.0, 1e-12);
  EXPECT_NEAR(s.fp, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.fn, 1.0 / 2.0, 1e-12);

  const std::vector<RoadLine> too_many{a, b, far_off, a, b};
  const LaneEvalScore t = lane_eval_frame(lanes, rows, c.camera.Nu, cam, too_many);
  EXPECT_EQ(t.accuracy, 0.0);
  EXPECT_EQ(t.fn, 1.0);

  // Five lanes, four of them on line a and one 50 px off it: the worst is left out.
  std::vector<AnnotatedLane> five(4, lane_a);
  five.push_back(lane_along(cam, a, 50.0, 400, 490));
  const LaneEvalScore f = lane_eval_frame(five, rows, c.camera.Nu, cam, {&a, 1});
  EXPECT_NEAR(f.accuracy, 1.0, 1e-12);
  EXPECT_EQ(f.fn, 0.0);
}

}  // namespace
}  // namespace ccdlane::cli
