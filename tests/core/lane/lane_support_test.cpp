// The support checks on values whose answer is known: marks of paint of one road width
// (width px = k / distance) slope -1, bars of one pixel width slope 0; spans, ranges and
// prior agreement at and either side of their limits; paint width spread, clutter in the
// lane and the motion a lane implies.
#include "core/lane/lane_support.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

MarkCandidate mark(int line, double X_mm, double width_px) {
  MarkCandidate m;
  m.line = static_cast<std::int16_t>(line);
  m.X = X_mm;
  m.left_px = 100.0;
  m.right_px = 100.0 + width_px;
  return m;
}

TEST(LaneSupport, PaintOfOneRoadWidthSlopesMinusOneAndBarsOfOnePixelWidthZero) {
  std::vector<MarkCandidate> marks;
  for (double x = 4000; x <= 30000; x += 2000) {
    marks.push_back(mark(0, x, 130.0 * 1200.0 / x));  // paint: px = k / distance
    marks.push_back(mark(1, x, 6.0));                 // a bar: the same pixels at every distance
    marks.push_back(mark(-1, x, 50.0));               // ungrouped: ignored
  }
  EXPECT_NEAR(width_distance_slope(marks, 0, false), -1.0, 1e-12);
  EXPECT_NEAR(width_distance_slope(marks, 1, false), 0.0, 1e-12);
  EXPECT_EQ(check_paint_width(width_distance_slope(marks, 0, false)), SupportProblem::none);
  EXPECT_EQ(check_paint_width(width_distance_slope(marks, 1, false)), SupportProblem::not_paint);
  EXPECT_EQ(check_paint_width(-1.0 + kPaintWidthSlopeTolerance * 0.99), SupportProblem::none);
  EXPECT_EQ(check_paint_width(-1.0 + kPaintWidthSlopeTolerance * 1.01), SupportProblem::not_paint);
  EXPECT_EQ(check_paint_width(-1.0 - kPaintWidthSlopeTolerance * 1.01), SupportProblem::not_paint);
  // Undetermined slopes are no support: too few marks, or all at one distance.
  EXPECT_TRUE(std::isnan(width_distance_slope({marks.data(), 2}, 0, false)));
  const std::vector<MarkCandidate> one_distance{mark(0, 9000, 5), mark(0, 9000, 6), mark(0, 9000, 7)};
  EXPECT_TRUE(std::isnan(width_distance_slope(one_distance, 0, false)));
  EXPECT_EQ(check_paint_width(std::nan("")), SupportProblem::not_paint);
}

// Paint's slope is what most of its marks say. Noise frame (seed 53, frame 109): an 11 px
// bar over 7.5-17 m and one 1.5 px mark of something else at 37 m; least squares sloped
// it -0.6, as paint, and with a thin bar beside it the frame was a lane.
TEST(LaneSupport, APaintLinesSlopeIsWhatMostOfItsMarksSay) {
  std::vector<MarkCandidate> marks;
  for (double x = 7500; x <= 17000; x += 250) marks.push_back(mark(0, x, 11.0));
  marks.push_back(mark(0, 37000, 1.5));
  EXPECT_LT(width_distance_slope(marks, 0, false), -0.25);  // least squares: the far mark's
  EXPECT_NEAR(paint_width_slope(marks, 0), 0.0, 1e-12);
  EXPECT_EQ(check_paint_width(paint_width_slope(marks, 0)), SupportProblem::not_paint);
  // Paint whose far end a row cuts (a quarter of its width) and with one blob beside it
  // near the car keeps its slope.
  std::vector<MarkCandidate> paint;
  for (double x = 5000; x <= 25000; x += 500) paint.push_back(mark(1, x, 60000.0 / x));
  paint.push_back(mark(1, 25500, 0.25 * 60000.0 / 25500));
  paint.push_back(mark(1, 5200, 30.0));
  EXPECT_NEAR(paint_width_slope(paint, 1), -1.0, 1e-12);
  // Undetermined as the least-squares slope is; dots are not paint's marks.
  EXPECT_TRUE(std::isnan(paint_width_slope({paint.data(), 2}, 1)));
  const std::vector<MarkCandidate> one_distance{mark(0, 9000, 5), mark(0, 9000, 6), mark(0, 9000, 7)};
  EXPECT_TRUE(std::isnan(paint_width_slope(one_distance, 0)));
  std::vector<MarkCandidate> dots = paint;
  for (MarkCandidate& m : dots) m.dot = true;
  EXPECT_TRUE(std::isnan(paint_width_slope(dots, 1)));
  // segA frame 121's right line, as detected: three dashes reading 9, 9 and 6 px. Paired
  // half the line apart its marks sloped -0.11 (not paint); every pair says paint.
  const double segA[][2] = {{8449, 8.82},  {8609, 8.50},  {9120, 8.82},  {9302, 8.72},  {9494, 8.58},
                            {9899, 9.67},  {11329, 9.03}, {11897, 7.89}, {12522, 6.50}, {16178, 9.60},
                            {16544, 11.62}, {16932, 9.36}, {17336, 9.39}, {17758, 10.15}, {18202, 9.16},
                            {18669, 8.52}, {19158, 9.40}, {19676, 8.30}, {20220, 8.93}, {31518, 5.12},
                            {32202, 6.24}, {32922, 6.66}, {33675, 6.75}, {34465, 6.03}, {35287, 6.29},
                            {36149, 4.08}};
  std::vector<MarkCandidate> dashes;
  for (const auto& [x, w] : segA) dashes.push_back(mark(3, x, w));
  EXPECT_EQ(check_paint_width(paint_width_slope(dashes, 3)), SupportProblem::none) << paint_width_slope(dashes, 3);
  // A line longer than the buffer is taken every k-th mark: the same slope.
  std::vector<MarkCandidate> long_line;
  for (int i = 0; i < 1000; ++i) long_line.push_back(mark(2, 4000.0 + 30.0 * i, 90000.0 / (4000.0 + 30.0 * i)));
  EXPECT_NEAR(paint_width_slope(long_line, 2), -1.0, 1e-12);
}

TEST(LaneSupport, ALineNeedsMarksOverEnoughRoadInsideTheSearchedRange) {
  const DetectionConfig d;  // 3..40 m searched, min_marks 8
  std::vector<Pick> picks;
  std::vector<Vec2> points;
  for (int i = 0; i < 10; ++i) {
    picks.push_back({0, 0.0, 0.0});
    points.emplace_back(5000.0 + 1000.0 * i, 1800.0);  // 5..14 m: 9 m of road
    picks.push_back({1, 0.0, 0.0});
    points.emplace_back(5000.0 + 500.0 * i, -1800.0);  // 5..9.5 m: too short
  }
  const LineSupport s0 = line_support(picks, points, 0);
  EXPECT_EQ(s0.marks, 10);
  EXPECT_DOUBLE_EQ(s0.near_mm, 5000.0);
  EXPECT_DOUBLE_EQ(s0.far_mm, 14000.0);
  EXPECT_EQ(check_line_support(s0, d), SupportProblem::none);
  EXPECT_EQ(check_line_support(line_support(picks, points, 1), d), SupportProblem::too_short);
  EXPECT_EQ(check_line_support({7, 5000.0, 20000.0}, d), SupportProblem::too_few_marks);
  EXPECT_EQ(check_line_support({8, 5000.0, 40000.0 * kRangeSlack * 1.01}, d), SupportProblem::out_of_range);
  EXPECT_EQ(check_line_support({8, 3000.0 / kRangeSlack * 0.99, 20000.0}, d), SupportProblem::out_of_range);
  // A short searched range asks for half of it.
  DetectionConfig near = d;
  near.max_range_mm = 12000.0;  // 9 m searched: 4.5 m of road suffice
  EXPECT_EQ(check_line_support({8, 5000.0, 9600.0}, near), SupportProblem::none);
  EXPECT_EQ(check_line_support({8, 5000.0, 9400.0}, near), SupportProblem::too_short);
}

// A run of bars 5..9 m ahead and one bar far beyond it, on the line through them by
// chance (a bright bar of noise near the vanishing point): the lone bar does not make
// the line long. One a dash's gap beyond the run does.
TEST(LaneSupport, AnIsolatedEndMarkDoesNotLengthenALine) {
  const DetectionConfig d;
  for (const double lone_mm : {30000.0, 20000.0}) {
    std::vector<Pick> picks;
    std::vector<Vec2> points;
    for (int i = 0; i < 10; ++i) {
      picks.push_back({0, 0.0, 0.0});
      points.emplace_back(5000.0 + 450.0 * i, 1800.0);
    }
    picks.push_back({0, 0.0, 0.0});
    points.emplace_back(lone_mm, 1800.0);
    const LineSupport s = line_support(picks, points, 0);
    EXPECT_EQ(s.marks, 11);
    EXPECT_DOUBLE_EQ(s.far_mm, lone_mm == 30000.0 ? 9050.0 : lone_mm);
    EXPECT_EQ(check_line_support(s, d), lone_mm == 30000.0 ? SupportProblem::too_short : SupportProblem::none);
  }
}

// One side of a lane may be a single dash (detection's min_dash_marks over
// min_dash_span_mm) beside a full line, in a lane of a common lane's width.
TEST(LaneSupport, ASingleDashNeedsItsMarksItsMetreTheRangeAndALanesWidth) {
  const DetectionConfig d;
  const GroupingParams g;  // 5 marks over 1 m
  const double w = 3600.0;
  EXPECT_TRUE(check_dash_support({5, 12000.0, 13000.0}, d, g, w));
  EXPECT_FALSE(check_dash_support({4, 12000.0, 13000.0}, d, g, w));
  EXPECT_FALSE(check_dash_support({5, 12000.0, 12990.0}, d, g, w));
  EXPECT_FALSE(check_dash_support({5, 40000.0 * kRangeSlack, 40000.0 * kRangeSlack * 1.1}, d, g, w));
  EXPECT_TRUE(check_dash_support({5, 12000.0, 13000.0}, d, g, kMinDashLaneWidthMm));
  EXPECT_FALSE(check_dash_support({5, 12000.0, 13000.0}, d, g, kMinDashLaneWidthMm - 1.0));
  EXPECT_TRUE(check_dash_support({5, 12000.0, 13000.0}, d, g, kMaxDashLaneWidthMm));
  EXPECT_FALSE(check_dash_support({5, 12000.0, 13000.0}, d, g, kMaxDashLaneWidthMm + 1.0));
}

TEST(LaneSupport, TheSolveMustAgreeWithItsPriors) {
  SolverPriors priors;
  priors.theta_deg = Prior{3.0, 0.5};
  priors.lane_width_mm = Prior{3600.0, 300.0};
  CameraPose pose;
  pose.attitude.theta = deg_to_rad(3.0 + 0.99 * kPriorAgreementSigmas * 0.5);
  EXPECT_EQ(check_priors(priors, pose, 3600.0), SupportProblem::none);
  pose.attitude.theta = deg_to_rad(3.0 - 1.01 * kPriorAgreementSigmas * 0.5);
  EXPECT_EQ(check_priors(priors, pose, 3600.0), SupportProblem::disagrees_with_prior);
  pose.attitude.theta = deg_to_rad(3.0);
  EXPECT_EQ(check_priors(priors, pose, 3600.0 + 1.01 * kPriorAgreementSigmas * 300.0),
            SupportProblem::disagrees_with_prior);
  // No prior, nothing to disagree with.
  EXPECT_EQ(check_priors(SolverPriors{}, pose, 99999.0), SupportProblem::none);
}

TEST(LaneSupport, PitchAndRollWithoutAPriorStayNearTheMounting) {
  Attitude mount;
  mount.theta = deg_to_rad(3.0);
  Attitude solved = mount;
  solved.phi = deg_to_rad(0.99 * kMaxBodyMotionDeg);
  EXPECT_EQ(check_body_motion(SolverPriors{}, solved, mount), SupportProblem::none);
  solved.phi = deg_to_rad(-1.01 * kMaxBodyMotionDeg);
  EXPECT_EQ(check_body_motion(SolverPriors{}, solved, mount), SupportProblem::attitude_off_mount);
  solved.phi = 0.0;
  solved.theta = deg_to_rad(3.0 + 1.01 * kMaxBodyMotionDeg);
  EXPECT_EQ(check_body_motion(SolverPriors{}, solved, mount), SupportProblem::attitude_off_mount);
  // With a prior (the gyro's), the prior's own check decides, not the mounting.
  SolverPriors gyro;
  gyro.theta_deg = Prior{9.0, 0.5};
  EXPECT_EQ(check_body_motion(gyro, solved, mount), SupportProblem::none);
}

TEST(LaneSupport, TheLaneRunsAlongTheVehiclesHeading) {
  EXPECT_EQ(check_heading(0.0), SupportProblem::none);
  EXPECT_EQ(check_heading(-0.99 * kMaxLaneHeadingDeg), SupportProblem::none);
  EXPECT_EQ(check_heading(1.01 * kMaxLaneHeadingDeg), SupportProblem::heading_off_lane);
  EXPECT_EQ(check_heading(-1.01 * kMaxLaneHeadingDeg), SupportProblem::heading_off_lane);
  EXPECT_EQ(check_heading(std::nan("")), SupportProblem::heading_off_lane);
}

// Paint of one road width gives log(width px x distance) one value for most marks;
// marks of bars of widths spread over detection's gate spread as far as that gate allows.
TEST(LaneSupport, PaintHasOneWidthOnTheRoadAMixOfBarsDoesNot) {
  const DetectionConfig d;  // 100..300 mm: a uniform mix deviates ln 3 / 4 = 0.275 from its median
  std::vector<MarkCandidate> marks;
  for (int i = 0; i < 40; ++i) {
    const double x = 5000.0 + 800.0 * i;
    marks.push_back(mark(0, x, 150.0 * 1200.0 / x * (i % 2 ? 1.1 : 0.9)));  // 150 mm, +-10 % edge noise
    const double bar_mm = 100.0 * std::pow(3.0, (i * 17 % 40 + 0.5) / 40.0);  // 100..300 mm, evenly in log
    marks.push_back(mark(1, x, bar_mm * 1200.0 / x));
    marks.push_back(mark(2, x, (i < 20 ? 110.0 : 280.0) * 1200.0 / x));  // a thin bar, then a wide one
    // A worn dash: the nearest third of the marks read 0.42 as wide (segA's right line).
    marks.push_back(mark(3, x, (i < 13 ? 0.42 : 1.0) * 150.0 * 1200.0 / x * (i % 2 ? 1.1 : 0.9)));
  }
  std::vector<double> scratch(marks.size());
  const auto spread = [&](int line) { return paint_width_spread(marks, line, scratch); };
  EXPECT_NEAR(spread(0), 0.1003, 1e-3);  // ln(1.1 / 0.9) / 2: every mark deviates as much
  EXPECT_NEAR(spread(1), std::log(3.0) / 4.0, 0.02);
  EXPECT_EQ(check_paint_width_spread(spread(0), d), SupportProblem::none);
  EXPECT_NEAR(spread(2), std::log(280.0 / 110.0) / 2.0, 1e-9);
  EXPECT_EQ(check_paint_width_spread(spread(2), d), SupportProblem::not_paint);
  EXPECT_EQ(check_paint_width_spread(spread(3), d), SupportProblem::none)
      << "a worn dash is paint of the same line (its standard deviation, 0.39, is a mix's)";
  EXPECT_EQ(check_paint_width_spread(0.99 * std::log(3.0) / 4.0, d), SupportProblem::none);
  EXPECT_EQ(check_paint_width_spread(1.01 * std::log(3.0) / 4.0, d), SupportProblem::not_paint);
  EXPECT_TRUE(std::isnan(paint_width_spread(std::span(marks).first(8), 0, scratch)));  // 2 marks of line 0
  EXPECT_EQ(check_paint_width_spread(std::nan(""), d), SupportProblem::not_paint);
  // At most scratch.size() marks: the first four of line 0 alone deviate 0.1 too.
  EXPECT_NEAR(paint_width_spread(marks, 0, std::span(scratch).first(4)), 0.1003, 1e-3);
}

// Marks inside the lane (a margin from either line) are measured in road length against
// the length its lines are seen over; the lines' marks and marks outside the lane are not
// clutter. An arrow's many marks near the vehicle take few metres; bars spread along the
// lane take many.
TEST(LaneSupport, ALaneFullOfMarksAlongItsLengthIsNotARoad) {
  const RoadLine left{1800.0, 0.0, 0.0}, right{-1800.0, 0.0, 0.0};
  std::vector<MarkCandidate> marks;
  const auto at = [](int line, double X, double Y) {
    MarkCandidate m;
    m.line = static_cast<std::int16_t>(line);
    m.X = X;
    m.Y = Y;
    return m;
  };
  for (double x = 4000.0; x < 40000.0; x += 500.0) {  // two solid lines over 4..40 m: 18 bins
    marks.push_back(at(0, x, 1800.0));
    marks.push_back(at(1, x, -1800.0));
    marks.push_back(at(2, x, -5400.0));  // the next lane's line: outside
    marks.push_back(at(-1, x, 3000.0));  // beside the road: outside
  }
  marks.push_back(at(-1, 8000.0, 1600.0));  // within the margin of the left line: not inside
  for (double x = 6100.0; x < 11000.0; x += 50.0) marks.push_back(at(-1, x, 0.0));  // an arrow, 5 m: 3 bins
  LaneClutter c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.line_bins, 18);
  EXPECT_EQ(c.inside_bins, 3);
  EXPECT_EQ(check_clutter(c), SupportProblem::none);
  for (double x = 14000.0; x < 26000.0; x += 2000.0) marks.push_back(at(-1, x + 500.0, -700.0));  // 6 bars more
  c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.inside_bins, 9);
  EXPECT_EQ(check_clutter(c), SupportProblem::none);  // half the lines' length: still a road
  marks.push_back(at(-1, 30500.0, 900.0));
  c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.inside_bins, 10);
  EXPECT_EQ(c.inside_marks, 105);  // the arrow's 98 among them
  EXPECT_EQ(c.line_marks, 144);
  EXPECT_EQ(check_clutter(c), SupportProblem::cluttered_lane);
}

// Patched concrete: a bar or two every couple of metres along the whole lane (slab edges,
// tar) is marked along as much road as the lines are, but sparsely; a field of bars as
// dense as the lines is not a road.
TEST(LaneSupport, SparseBarsAlongTheLaneAreARoadDenseOnesAreNot) {
  const RoadLine left{1800.0, 0.0, 0.0}, right{-1800.0, 0.0, 0.0};
  std::vector<MarkCandidate> marks;
  const auto add = [&marks](int line, double X, double Y) {
    MarkCandidate m;
    m.line = static_cast<std::int16_t>(line);
    m.X = X;
    m.Y = Y;
    marks.push_back(m);
  };
  for (double x = 4000.0; x < 40000.0; x += 500.0) {  // 18 bins, 144 marks
    add(0, x, 1800.0);
    add(1, x, -1800.0);
  }
  for (double x = 4100.0; x < 40000.0; x += 1000.0) add(-1, x, 400.0 * std::sin(x));  // 36 bars in 18 bins
  LaneClutter c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.inside_bins, 18);
  EXPECT_EQ(c.inside_marks, 36);
  EXPECT_EQ(check_clutter(c), SupportProblem::none);
  for (double x = 4300.0; x < 40000.0; x += 1000.0) add(-1, x, -400.0);  // 36 more: 72 of 144
  EXPECT_EQ(check_clutter(lane_clutter(marks, left, 0, right, 1, 300.0)), SupportProblem::none);
  add(-1, 20000.0, 0.0);  // one more than half the lines' marks
  EXPECT_EQ(check_clutter(lane_clutter(marks, left, 0, right, 1, 300.0)), SupportProblem::cluttered_lane);
}

// A noisy picture fills a lane with faint bars, a field of bars with bars as strong as the
// chance lines it makes of them. Inside a lane whose lines continue a tracked lane's
// (faint_share), marks fainter than a quarter of the lines' median contrast are the
// picture's noise, not clutter; as strong as that, they still are.
TEST(LaneSupport, FaintBarsInsideATrackedLaneAreThePicturesNoiseNotClutter) {
  const RoadLine left{1800.0, 0.0, 0.0}, right{-1800.0, 0.0, 0.0};
  std::vector<MarkCandidate> marks;
  const auto add = [&marks](int line, double X, double Y, double contrast) {
    MarkCandidate m;
    m.line = static_cast<std::int16_t>(line);
    m.X = X;
    m.Y = Y;
    m.contrast = contrast;
    marks.push_back(m);
  };
  for (double x = 4000.0; x < 40000.0; x += 500.0) {  // 18 bins, 144 marks; median contrast 120
    add(0, x, 1800.0, 100.0 + 40.0 * (static_cast<int>(x / 500.0) % 2));
    add(1, x, -1800.0, 110.0 + 20.0 * (static_cast<int>(x / 500.0) % 2));
  }
  add(0, 20250.0, 1800.0, 120.0);  // one more: the median is 120, not between two
  for (double x = 4100.0; x < 40000.0; x += 400.0) add(-1, x, 600.0 * std::sin(x), 29.0);  // 90 faint bars
  const double tracked = kTrackedFaintClutterShare;
  LaneClutter c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.inside_marks, 90);
  EXPECT_EQ(c.faint_marks, 0);
  EXPECT_EQ(check_clutter(c), SupportProblem::cluttered_lane) << "on a search every bar counts";
  c = lane_clutter(marks, left, 0, right, 1, 300.0, nullptr, tracked);
  EXPECT_EQ(c.inside_marks, 0);
  EXPECT_EQ(c.faint_marks, 90);
  EXPECT_EQ(check_clutter(c), SupportProblem::none);
  // A quarter of 120 is 30: bars of that contrast are clutter, tracked or not.
  for (MarkCandidate& m : marks)
    if (m.line < 0) m.contrast = 30.0;
  c = lane_clutter(marks, left, 0, right, 1, 300.0, nullptr, tracked);
  EXPECT_EQ(c.inside_marks, 90);
  EXPECT_EQ(c.faint_marks, 0);
  EXPECT_EQ(check_clutter(c), SupportProblem::cluttered_lane);
}

// A truck ahead in the lane: its upright edges project onto the lane's far half as bars,
// one on every scan row, each overlapping the one on the row before (TuSimple stills 43
// and 75). That is one thing standing in the lane, not a field of bars; the same bars
// scattered across the lane from row to row are.
TEST(LaneSupport, BarsRunningOnFromRowToRowAreAThingInTheLaneNotClutter) {
  const RoadLine left{1800.0, 0.0, 0.0}, right{-1800.0, 0.0, 0.0};
  std::vector<MarkCandidate> marks;
  const auto add = [&marks](int line, int scan_row, double X, double Y, double px) {
    MarkCandidate m;
    m.line = static_cast<std::int16_t>(line);
    m.scan_row = static_cast<std::int16_t>(scan_row);
    m.X = X;
    m.Y = Y;
    m.left_px = px - 3.0;
    m.right_px = px + 3.0;
    marks.push_back(m);
  };
  // Scan rows far to near. The lines: 19 bins of 2 m, 144 marks. The truck's edge: 80
  // bars over the 20 m beyond 20 m (11 bins), more than half the lines' marks.
  const auto road = [&](double truck_px_odd_rows) {
    marks.clear();
    for (int row = 0; row < 80; ++row)
      add(-1, row, 40000.0 - 250.0 * row, 200.0, row % 2 == 0 ? 640.0 : truck_px_odd_rows);
    for (int k = 0; k < 72; ++k) {
      add(0, 80 + k, 40000.0 - 500.0 * k, 1800.0, 100.0);
      add(1, 80 + k, 40000.0 - 500.0 * k, -1800.0, 1200.0);
    }
  };
  road(642.0);  // each bar overlaps the next: one edge running on
  LaneClutter c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.standing_marks, 80);
  EXPECT_EQ(c.inside_marks, 0);
  EXPECT_EQ(check_clutter(c), SupportProblem::none);
  road(700.0);  // every other bar 60 px aside: nothing runs on
  c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.standing_marks, 0);
  EXPECT_EQ(c.inside_marks, 80);
  EXPECT_EQ(c.inside_bins, 11);
  EXPECT_EQ(check_clutter(c), SupportProblem::cluttered_lane);
  // Runs of three scan rows are chance alignments: still clutter.
  road(640.0);
  for (int row = 3; row < 80; row += 3) marks[static_cast<std::size_t>(row)].left_px += 100.0;
  for (int row = 3; row < 80; row += 3) marks[static_cast<std::size_t>(row)].right_px += 100.0;
  c = lane_clutter(marks, left, 0, right, 1, 300.0);
  EXPECT_EQ(c.standing_marks, 0);
  EXPECT_EQ(check_clutter(c), SupportProblem::cluttered_lane);
}

// Two lanes look like one of a lane's width from a height taken half as high: their
// outer lines bound the "lane", and the line between them runs inside it. A dashed line
// (bars running on over a dash's scan rows, at one offset, in separate dashes) or a row
// of raised markers (dots at one offset, fewer along a joint) is a line inside; one dash,
// an arrow, dashes at scattered offsets or a row of markers beside a border are not.
TEST(LaneSupport, ALineInsideTheLaneIsOneBetweenTwoLanes) {
  const RoadLine left{3700.0, 0.0, 0.0}, right{-3700.0, 0.0, 0.0};
  std::vector<MarkCandidate> marks;
  // Scan rows one every 250 mm of road, far to near; a bar's column follows its offset.
  const auto add = [&marks](int line, double X, double Y) -> MarkCandidate& {
    MarkCandidate m;
    m.line = static_cast<std::int16_t>(line);
    m.scan_row = static_cast<std::int16_t>((50000.0 - X) / 250.0);
    m.X = X;
    m.Y = Y;
    m.left_px = 640.0 - Y / 10.0 - 3.0;
    m.right_px = 640.0 - Y / 10.0 + 3.0;
    marks.push_back(m);
    return marks.back();
  };
  const auto dash = [&](double from_X, double Y) {  // 3 m: 12 scan rows
    for (double x = from_X; x < from_X + 3000.0; x += 250.0) add(-1, x, Y);
  };
  const auto dot = [&](double X, double Y) { add(-1, X, Y).dot = true; };
  const auto inside = [&] {
    for (double x = 5000.0; x < 45000.0; x += 250.0) add(0, x, 3700.0), add(1, x, -3700.0);
    std::stable_sort(marks.begin(), marks.end(),
                     [](const MarkCandidate& a, const MarkCandidate& b) { return a.scan_row < b.scan_row; });
    InsidePieces line;
    lane_clutter(marks, left, 0, right, 1, 300.0, &line);
    marks.clear();
    return line;
  };

  for (const double x : {6000.0, 18000.0, 30000.0}) dash(x, 100.0);
  InsidePieces p = inside();
  EXPECT_EQ(p.dashes, 3);
  EXPECT_TRUE(is_line_inside(p));

  dash(6000.0, 100.0);  // one dash, an arrow's shaft, a vehicle's edge
  EXPECT_FALSE(is_line_inside(inside()));
  for (double x = 6000.0; x < 11000.0; x += 250.0) add(-1, x, 0.0);  // an arrow, 5 m
  EXPECT_FALSE(is_line_inside(inside()));
  const double scattered[] = {-1200.0, -400.0, 400.0, 1200.0};  // 0.8 m apart
  for (int k = 0; k < 4; ++k) dash(6000.0 + 10000.0 * k, scattered[k]);
  EXPECT_FALSE(is_line_inside(inside()));
  for (const double x : {6000.0, 18000.0, 30000.0}) dash(x, 2900.0);  // 0.8 m from the left line
  EXPECT_FALSE(is_line_inside(inside()));

  for (const double x : {6000.0, 9700.0, 13400.0, 17000.0}) dot(x, -100.0);  // 3.66 m apart
  p = inside();
  EXPECT_EQ(p.dots, 4);
  EXPECT_TRUE(is_line_inside(p));
  for (const double x : {6000.0, 9700.0, 13400.0}) dot(x, -100.0);
  EXPECT_FALSE(is_line_inside(inside()));
  // The same three set along a joint (a joint no line took: a seam alone is no line).
  for (const double x : {6000.0, 9700.0, 13400.0}) dot(x, -100.0);
  for (double x = 5000.0; x < 15000.0; x += 500.0) add(-1, x, -150.0).joint = true;
  p = inside();
  EXPECT_EQ(p.joints, 6);  // 2 m bins
  EXPECT_TRUE(is_line_inside(p));
  for (double x = 5000.0; x < 15000.0; x += 500.0) add(-1, x, -150.0).joint = true;
  EXPECT_FALSE(is_line_inside(inside()));
}

// A car's lateral speed and acceleration bound what heading and curvature a lane it
// follows can have at the speed driven.
TEST(LaneSupport, TheLanesHeadingAndBendMustBeDrivableAtTheSpeed) {
  const double v = 25.0;  // 90 km/h
  const double max_heading = rad_to_deg(std::asin(kMaxLateralSpeedMps / v));
  EXPECT_EQ(check_motion(v, 0.99 * max_heading, 0.0), SupportProblem::none);
  EXPECT_EQ(check_motion(v, -1.01 * max_heading, 0.0), SupportProblem::implausible_motion);
  const double max_curvature = kMaxLateralAccelerationMps2 / (v * v);  // R 156 m at 90 km/h
  EXPECT_EQ(check_motion(v, 0.0, -0.99 * max_curvature), SupportProblem::none);
  EXPECT_EQ(check_motion(v, 0.0, 1.01 * max_curvature), SupportProblem::implausible_motion);
  // Slowly, a town's tight corner and a steep heading are driven.
  EXPECT_EQ(check_motion(5.0, 8.0, 1.0 / 15.0), SupportProblem::none);
  EXPECT_EQ(check_motion(0.0, 9.9, 1.0), SupportProblem::none);
}

// From one frame to the next an own line moves as far as the vehicle moves sideways, plus
// its offset's own scatter; half a lane or more away, it is the line beside (a lane
// change); in between, something else taken for the line.
TEST(LaneSupport, AnOwnLineMovesFromFrameToFrameAsTheVehicleDoes) {
  const double dt = 0.04, width = 3660.0;
  const double allowed = kMaxLateralSpeedMps * 1000.0 * dt + kOwnLineStepSlackMm;  // 480 mm
  EXPECT_FALSE(own_line_jumped(-1800.0, -1800.0, dt, width));
  EXPECT_FALSE(own_line_jumped(-1800.0 - 0.99 * allowed, -1800.0, dt, width));
  EXPECT_TRUE(own_line_jumped(-1800.0 - 1.01 * allowed, -1800.0, dt, width));
  EXPECT_TRUE(own_line_jumped(1800.0 + 1.01 * allowed, 1800.0, dt, width));  // either way
  // A lane change: the line beside, a lane away, becomes the own line.
  EXPECT_FALSE(own_line_jumped(-1800.0 - 0.5 * width, -1800.0, dt, width));
  EXPECT_FALSE(own_line_jumped(-1800.0 - width, -1800.0, dt, width));
  // Frames without a lane in between: the vehicle may have moved farther meanwhile.
  EXPECT_FALSE(own_line_jumped(-1800.0 - 1.01 * allowed, -1800.0, 0.25, width));
  // A frame time that went backwards (a replayed log's clock) allows the slack alone.
  EXPECT_TRUE(own_line_jumped(-1800.0 - 1.01 * kOwnLineStepSlackMm, -1800.0, -1.0, width));
}

// From one frame to the next the yaw turns as fast as a vehicle turns, plus its own
// scatter; faster, the lane is fitted to something else.
TEST(LaneSupport, TheYawTurnsFromFrameToFrameAsAVehicleDoes) {
  const double dt = 0.04;
  const double allowed = kMaxYawRateDegPerS * dt + kYawStepSlackDeg;  // 1.8 degrees
  EXPECT_FALSE(yaw_jumped(0.3, 0.3, dt));
  EXPECT_FALSE(yaw_jumped(0.3 + 0.99 * allowed, 0.3, dt));
  EXPECT_TRUE(yaw_jumped(0.3 + 1.01 * allowed, 0.3, dt));
  EXPECT_TRUE(yaw_jumped(0.3 - 1.01 * allowed, 0.3, dt));
  // Frames without a lane in between: the vehicle may have turned farther meanwhile.
  EXPECT_FALSE(yaw_jumped(0.3 + 1.01 * allowed, 0.3, 0.2));
  // A frame time that went backwards allows the slack alone.
  EXPECT_TRUE(yaw_jumped(1.01 * kYawStepSlackDeg, 0.0, -1.0));
}

// A picture seen from 0.75 m where the camera is 1.65 m up: the own left line and the next
// lane's right line make a lane of 3.68 m; seen from 1.65 m, the own lane's lines make one
// of 3.7 m. Taken to 0.75 m, the second's left line lies on the first's and its right line
// inside it: the first is two lanes.
TEST(LaneSupport, ALaneWithAnotherHeightsLaneLineInsideItIsTwoLanes) {
  const OwnLanePlace two_lanes{860.0, -2820.0, 750.0};
  const OwnLanePlace own{1850.0, -1850.0, 1650.0};  // at 0.75 m: 841 and -841 mm
  EXPECT_TRUE(spans_two_lanes(two_lanes, own));
  EXPECT_FALSE(spans_two_lanes(own, two_lanes));  // the narrower lane holds no line of the wider
  // The same lane found from two heights is one lane at either scale.
  EXPECT_FALSE(spans_two_lanes(own, OwnLanePlace{1850.0 * 0.8, -1850.0 * 0.8, 1650.0 * 0.8}));
  // Mirrored: the right lines shared, the left one inside.
  EXPECT_TRUE(spans_two_lanes(OwnLanePlace{2820.0, -860.0, 750.0}, own));
  // The shared line must lie on the other's, within a tenth of the wide lane's width.
  const double width = two_lanes.left_mm - two_lanes.right_mm, scale = 750.0 / 1650.0;
  const double off = (kSharedLineShare * width + 30.0) / scale;
  EXPECT_FALSE(spans_two_lanes(two_lanes, OwnLanePlace{1850.0 + off, -1850.0, 1650.0}));
  // And the inner line at least kInsideLineFromSide of the width from both: a line beside
  // one of the wide lane's lines is its shadow or a second stripe, no lane line.
  const double near_right = (two_lanes.right_mm + 0.9 * kInsideLineFromSide * width) / scale;
  EXPECT_FALSE(spans_two_lanes(two_lanes, OwnLanePlace{1850.0, near_right, 1650.0}));
  // Without a lane on either side, or a height, nothing is shown.
  EXPECT_FALSE(spans_two_lanes(OwnLanePlace{}, own));
  EXPECT_FALSE(spans_two_lanes(two_lanes, OwnLanePlace{}));
}

// Without a measured speed a bend is judged at the configured speed while that can take
// it, else at the speed a car takes it at, down to kMinUnmeasuredSpeedMps; a measured
// speed is always the one.
TEST(LaneSupport, WithoutASpeedABendIsJudgedAtTheSpeedItIsTakenAt) {
  const double configured = 20.0;  // 72 km/h: bends down to 100 m radius
  EXPECT_EQ(judged_speed_mps(30.0, configured, 1.0 / 50.0), 30.0);
  EXPECT_EQ(judged_speed_mps(std::nullopt, configured, 1.0 / 150.0), configured);
  EXPECT_EQ(judged_speed_mps(std::nullopt, configured, -1.0 / 100.0), configured);
  for (const double radius_m : {99.0, 60.0, 25.5}) {
    const double v = judged_speed_mps(std::nullopt, configured, -1.0 / radius_m);
    EXPECT_NEAR(v, std::sqrt(kMaxLateralAccelerationMps2 * radius_m), 1e-6) << radius_m;
    EXPECT_EQ(check_motion(v, 0.0, -1.0 / radius_m), SupportProblem::none) << radius_m;
  }
  // Sharper than a car takes at kMinUnmeasuredSpeedMps (25 m): no lane a car follows.
  const double v = judged_speed_mps(std::nullopt, configured, 1.0 / 20.0);
  EXPECT_EQ(v, kMinUnmeasuredSpeedMps);
  EXPECT_EQ(check_motion(v, 0.0, 1.0 / 20.0), SupportProblem::implausible_motion);
  // And a lane's heading is judged at that speed too.
  EXPECT_EQ(check_motion(judged_speed_mps(std::nullopt, configured, 0.0), 6.0, 0.0),
            SupportProblem::implausible_motion);
}

}  // namespace
}  // namespace ccdlane
