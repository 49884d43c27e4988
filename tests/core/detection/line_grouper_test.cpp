// Grouping marks into lines on the road: lines among clutter, continuation of the
// previous frame's lines, separation (and which of two lines too near each other
// stands), the nearest lines kept, sparse clutter refused.
#include "core/detection/line_grouper.hpp"

#include <cmath>
#include <initializer_list>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

// What the row filter measures of paint (and of the clutter here, at its worst), grey
// levels over the road beside it.
constexpr double kPaintContrast = 60.0;

struct Scene {
  std::vector<MarkCandidate> marks;
  std::mt19937 rng{7};
  // A mark on every scan row from near to far (`every` > 1: dashes), with lateral noise
  // of noise_px pixels (a pixel spans X / 630 mm at distance X).
  void line(double y0, double m, double c, double noise_px = 0.3, int every = 1, bool yellow = false,
            bool for_lines_beyond = false) {
    std::normal_distribution<double> n(0.0, 1.0);
    for (int row = 0; row < 150; ++row) {
      if ((row / 4) % every) continue;
      const double X = 5000.0 + 35000.0 * row / 149.0;
      MarkCandidate mk;
      mk.X = X;
      mk.contrast = kPaintContrast;
      mk.yellow = yellow;
      mk.for_lines_beyond = for_lines_beyond;
      mk.Y = y0 + m * X + c * X * X + noise_px * X / 630.0 * n(rng);
      mk.scan_row = static_cast<std::int16_t>(row);
      marks.push_back(mk);
    }
  }
  // A mark of this contrast on every scan row between near_mm and far_mm, on a straight
  // line through y_ref at x_ref with this slope (a dash, or a faint stretch of old paint).
  void stretch(double y_ref, double x_ref, double slope, double near_mm, double far_mm, double contrast) {
    for (int row = 0; row < 150; ++row) {
      const double X = 5000.0 + 35000.0 * row / 149.0;
      if (X < near_mm || X > far_mm) continue;
      MarkCandidate mk;
      mk.X = X;
      mk.Y = y_ref + slope * (X - x_ref);
      mk.contrast = contrast;
      mk.scan_row = static_cast<std::int16_t>(row);
      marks.push_back(mk);
    }
  }
  // Five raised markers 2.5 m apart from 15 m in (far to near, as rows come), 10 cm
  // across (narrower with distance), each on one of the 30 scan rows to the next: on the
  // line through y_ref at x_ref with this slope.
  void dots(double y_ref, double slope, double x_ref = 0.0) {
    for (int k = 0; k < 5; ++k) {
      MarkCandidate mk;
      mk.X = 15000.0 - 2500.0 * k;
      mk.Y = y_ref + slope * (mk.X - x_ref);
      mk.contrast = kPaintContrast;
      const double width_px = 630.0 * 100.0 / mk.X;
      mk.left_px = 600.0 - 0.5 * width_px;
      mk.right_px = 600.0 + 0.5 * width_px;
      mk.scan_row = static_cast<std::int16_t>(100 + 30 * k);
      mk.dot = true;
      mk.dot_top = static_cast<std::int16_t>(mk.scan_row - 1);
      mk.dot_bottom = static_cast<std::int16_t>(mk.scan_row + 1);
      marks.push_back(mk);
    }
  }
  // The sealed joint between two concrete slabs along the road: a dark line a piece of
  // which is found on every scan row, meandering across it by up to `meander_rad` of
  // the camera's view (a sine over a few rows: the rms is 0.71 of it).
  void joint(double y0, double m, double meander_rad = 0.0) {
    for (int row = 0; row < 150; ++row) {
      MarkCandidate mk;
      mk.X = 5000.0 + 35000.0 * row / 149.0;
      mk.Y = y0 + m * mk.X + meander_rad * mk.X * std::sin(0.7 * row);
      mk.contrast = kPaintContrast;
      const double width_px = 3.0;
      mk.left_px = 600.0 - 0.5 * width_px;
      mk.right_px = 600.0 + 0.5 * width_px;
      mk.scan_row = static_cast<std::int16_t>(row);
      mk.joint = true;
      marks.push_back(mk);
    }
  }
  void clutter(int count) {
    std::uniform_real_distribution<double> x(5000, 40000), y(-12000, 12000);
    std::uniform_int_distribution<int> row(0, 149);
    for (int i = 0; i < count; ++i) {
      MarkCandidate mk;
      mk.X = x(rng);
      mk.Y = y(rng);
      mk.contrast = kPaintContrast;
      mk.scan_row = static_cast<std::int16_t>(row(rng));
      marks.push_back(mk);
    }
  }
};

// `tracked`: the priors are a tracked frame's (GroupingParams::tracked_priors).
int group(Scene& s, std::array<DetectedLine, kMaxDetectedLines>& lines, std::span<const RoadLine> priors = {},
          int max_lines = 4, bool tracked = false) {
  LineGrouper g(4096);
  GroupingParams p;
  p.max_lines = max_lines;
  p.mm_per_px_per_mm = 1.0 / 630.0;
  p.tracked_priors = tracked;
  return g.group(s.marks, priors, p, lines);
}

TEST(LineGrouper, FindsSolidAndDashedLinesAmongClutter) {
  Scene s;
  s.line(5400, 0.01, 0.0);
  s.line(1800, 0.01, 0.0, 0.3, 3);  // dashed
  s.line(-1800, 0.01, 0.0);
  s.clutter(300);
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines), 3);
  const double want[3] = {5400, 1800, -1800};
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(lines[j].fit.y0_mm, want[j], 30.0) << j;
    EXPECT_NEAR(lines[j].fit.m, 0.01, 0.002) << j;
    EXPECT_EQ(lines[j].prior_index, -1);
    EXPECT_LT(lines[j].rms_mm, 20.0);
  }
  EXPECT_NEAR(lines[0].marks, 150, 10);
  EXPECT_NEAR(lines[1].marks, 52, 6);
  // Marks carry their line's index; clutter stays ungrouped (bar the few on a line).
  int grouped = 0;
  for (const MarkCandidate& m : s.marks) grouped += m.line >= 0;
  EXPECT_NEAR(grouped, 150 + 52 + 150, 12);
}

TEST(LineGrouper, CurvedLinesFitTheirCurvature) {
  Scene s;
  s.line(1700, -0.005, 2e-7);
  s.line(-1900, -0.005, 2e-7);
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines), 2);
  EXPECT_NEAR(lines[0].fit.c_per_mm, 2e-7, 2e-8);
  EXPECT_NEAR(lines[1].fit.y0_mm, -1900, 30);
}

// One 3 m dash of a dashed line on a bend, its others in the gaps or beyond the range:
// too short for a line of its own slope (min_span_mm), found as the parallel of the
// road's other lines, with its y0 alone fitted. One dash of clutter elsewhere (a mark
// every row, but off the road's direction) is not.
TEST(LineGrouper, ASingleDashParallelToTheRoadsLinesIsALine) {
  Scene s;
  const double c = 1.0 / (2.0 * 400e3);  // R 400 m
  s.line(5400, 0.01, c);
  s.line(-1800, 0.01, c);
  std::normal_distribution<double> n(0.0, 0.3);
  for (int row = 40; row < 48; ++row) {  // the dash: 8 rows, X from 14.4 to 16.1 m
    const double X = 5000.0 + 35000.0 * row / 149.0;
    MarkCandidate mk;
    mk.contrast = kPaintContrast;
    mk.X = X;
    mk.Y = 1800 + 0.01 * X + c * X * X + X / 630.0 * n(s.rng);
    mk.scan_row = static_cast<std::int16_t>(row);
    s.marks.push_back(mk);
  }
  for (int row = 60; row < 68; ++row) {  // across the road's direction: a slope of 0.3
    const double X = 5000.0 + 35000.0 * row / 149.0;
    MarkCandidate mk;
    mk.contrast = kPaintContrast;
    mk.X = X;
    mk.Y = -9000 + 0.3 * (X - 20000.0);
    mk.scan_row = static_cast<std::int16_t>(row);
    s.marks.push_back(mk);
  }
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines), 3);
  EXPECT_NEAR(lines[1].fit.y_at(15000), 1800 + 0.01 * 15000 + c * 15000 * 15000, 30.0);
  EXPECT_EQ(lines[1].marks, 8);
  EXPECT_NEAR(lines[1].fit.m, 0.01, 0.002);  // the road's, not fitted to the dash
  EXPECT_NEAR(lines[1].fit.c_per_mm, c, 2e-8);
}

TEST(LineGrouper, ContinuesThePreviousFramesLines) {
  Scene s;
  s.line(1650, 0.0, 0.0);
  s.line(-1950, 0.0, 0.0, 0.3, 3);
  s.line(-5550, 0.0, 0.0);
  // The previous frame saw them 150 mm further left, listed in another order, plus a line
  // that has gone.
  const RoadLine priors[] = {{-5400, 0, 0}, {9000, 0, 0}, {1800, 0, 0}, {-1800, 0, 0}};
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines, priors), 3);
  EXPECT_EQ(lines[0].prior_index, 2);
  EXPECT_EQ(lines[1].prior_index, 3);
  EXPECT_EQ(lines[2].prior_index, 0);
  EXPECT_NEAR(lines[1].fit.y0_mm, -1950, 30);
}

// A tracked frame's line that misses the road's parabola along a smooth curve (a road
// not quite flat, a bend's changing curvature: here a flat-topped wave of 1.4 px over
// three periods of the range, 1.2 px rms about the best parabola and 1.7 px at most,
// over the scatter bound of 1.1 and within the fit's tolerance of 2)
// is continued from the previous frame's; a line of marks scattered as evenly over the
// fit's tolerance (about 1.15 px rms) is not, nor is the smooth one when the priors are a
// search's own first solve (founding a line, the bound stands). segA frame 183: its
// yellow edge line at 1.16 px, correlated 0.92 from mark to mark.
TEST(LineGrouper, ATrackedLineThatMissesItsParabolaSmoothlyIsContinued) {
  const auto scene = [](bool smooth) {
    Scene s;
    s.line(-1800, 0.0, 0.0);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int row = 0; row < 150; ++row) {
      const double X = 5000.0 + 35000.0 * row / 149.0, px = X / 630.0;
      const double off_px =
          smooth ? 1.4 * std::tanh(4.0 * std::sin(6.0 * 3.14159265 * (X - 5000.0) / 35000.0)) : u(s.rng);
      MarkCandidate mk;
      mk.X = X;
      mk.Y = 1800.0 + off_px * px;
      mk.contrast = kPaintContrast;
      mk.scan_row = static_cast<std::int16_t>(row);
      s.marks.push_back(mk);
    }
    return s;
  };
  const RoadLine priors[] = {{1800, 0, 0}, {-1800, 0, 0}};
  const auto left_line = [&](bool smooth, bool tracked) {
    Scene s = scene(smooth);
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    const int n = group(s, lines, priors, 4, tracked);
    for (int j = 0; j < n; ++j)
      if (lines[j].fit.y0_mm > 0.0) return lines[j];
    return DetectedLine{};
  };
  const DetectedLine kept = left_line(true, true);
  EXPECT_EQ(kept.prior_index, 0);
  EXPECT_FALSE(kept.parallel);
  EXPECT_GT(kept.marks, 120);
  EXPECT_GT(kept.rms_mm, 0.0);
  const DetectedLine founded = left_line(true, false);
  EXPECT_TRUE(founded.marks == 0 || founded.parallel || founded.prior_index != 0)
      << "a search's own line is held to the bound";
  const DetectedLine clutter = left_line(false, true);
  EXPECT_TRUE(clutter.marks == 0 || clutter.parallel || clutter.prior_index != 0) << "scatter is not a misfit";
}

// A tracked frame keeps the road's curvature for a line too short to show its own. Here
// the road is straight (the previous frame's lines, and a solid line the whole range),
// and beside it a run of marks 9 m long bows as a 125 m bend would: a parabola through
// three of its marks fits it, and once took its place as the line's curvature, though
// nine metres of marks cannot tell one (held TuSimple still 12: a row of dots kept such
// a bend beside a straight road's lines, and no solve converged on it for 16 frames).
TEST(LineGrouper, ATrackedFramesShortLineKeepsTheRoadsCurvature) {
  Scene s;
  s.line(1800, 0.0, 0.0);
  for (int row = 0; row < 150; ++row) {
    const double X = 5000.0 + 35000.0 * row / 149.0;
    if (X > 14000.0) continue;
    MarkCandidate mk;
    mk.X = X;
    mk.Y = -1800.0 - 4e-6 * (X - 9500.0) * (X - 9500.0);
    mk.contrast = kPaintContrast;
    mk.scan_row = static_cast<std::int16_t>(row);
    s.marks.push_back(mk);
  }
  const RoadLine priors[] = {{1800, 0, 0}, {-1800, 0, 0}};
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  const int n = group(s, lines, priors, 4, true);
  ASSERT_GE(n, 1);
  for (int j = 0; j < n; ++j)
    EXPECT_LT(std::abs(lines[j].fit.c_per_mm), 1e-7) << "line " << j << " at " << lines[j].fit.y0_mm << " mm";
}

// A dashed line with a dash near and one far, and between them a faint scar of old paint
// (or a tar seam) 15 cm inside the line: the scar has more marks than the dashes, the paint
// far more contrast. The line is the paint's.
TEST(LineGrouper, TheLineFollowsBrightPaintOverAFaintScarWithMoreMarks) {
  Scene s;
  s.line(1650, 0.0, 0.0);
  s.stretch(-1950, 0.0, 0.0, 6000, 9000, 80.0);
  s.stretch(-1950, 0.0, 0.0, 18000, 21000, 80.0);
  s.stretch(-1800, 0.0, 0.0, 9000, 18000, 12.0);
  const RoadLine priors[] = {{1650, 0, 0}, {-1950, 0, 0}};
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines, priors), 2);
  EXPECT_EQ(lines[1].prior_index, 1);
  EXPECT_NEAR(lines[1].fit.y0_mm, -1950, 30);
  EXPECT_NEAR(lines[1].fit.m, 0.0, 0.002);
}

// A previous frame took a barrier's foot (grey bars 3.4 m left) for the left line; the
// yellow edge line 1.6 m nearer, too near it to be a lane line of its own, is seen on
// half the rows (its other bars failed the row filter's step test). Yellow paint takes
// the foot's place; the same line in grey would not (it has fewer marks than the line
// it would replace).
TEST(LineGrouper, YellowPaintTakesThePlaceOfAGreyLineTooNearIt) {
  const RoadLine priors[] = {{3400, 0, 0}, {-1800, 0, 0}};
  for (const bool yellow : {true, false}) {
    Scene s;
    s.line(3400, 0.0, 0.0);
    s.line(1800, 0.0, 0.0, 0.3, 2, yellow);
    s.line(-1800, 0.0, 0.0);
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    ASSERT_EQ(group(s, lines, priors), 2) << "yellow " << yellow;
    EXPECT_NEAR(lines[0].fit.y0_mm, yellow ? 1800.0 : 3400.0, 30.0) << "yellow " << yellow;
    EXPECT_EQ(lines[0].yellow, yellow);
    EXPECT_FALSE(lines[1].yellow);
    EXPECT_NEAR(lines[1].fit.y0_mm, -1800.0, 30.0);
    for (const MarkCandidate& m : s.marks) {
      if (m.line == 0) {
        EXPECT_NEAR(m.Y, yellow ? 1800.0 : 3400.0, 300.0);
      }
    }
  }
}

// A row of five raised markers 2.5 m apart beside a solid line, too few for a line of its
// own (GroupingParams::min_dots) and covering few of the rows it spans, found along the
// road's direction (min_parallel_dots); its marks span 10 m, and it runs at a slope of its
// own (a pitch error tilts lines in proportion to their offset): the fit takes its slope,
// and keeps every dot within the dots' tolerance.
TEST(LineGrouper, AFewDotsParallelToALineFitTheirOwnSlopeWhenTheySpanEnough) {
  Scene s;
  s.line(1800, 0.0, 0.0);
  const double slope = 0.010;  // 50 mm either side of the solid line's direction over 10 m
  s.dots(-1800.0, slope);
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines), 2);
  EXPECT_TRUE(lines[1].parallel);
  EXPECT_TRUE(lines[1].dots);
  EXPECT_EQ(lines[1].marks, 5);
  EXPECT_NEAR(lines[1].fit.m, slope, 1e-6);
  EXPECT_NEAR(lines[1].fit.y0_mm, -1800.0, 0.1);
}

// Solid lines at `paint_y0s` (ordered left to right) and, right of them, a row of five
// dots through y_ref at 10 m running at `slope`: a row a pitch error may tilt so is found
// with its own slope (the rightmost line); one tilted more than any pitch error does is
// not a row along the road.
void expect_tilted_dot_row(std::initializer_list<double> paint_y0s, double y_ref, double slope, bool within_tilt) {
  Scene s;
  for (const double y0 : paint_y0s) s.line(y0, 0.0, 0.0);
  s.dots(y_ref, slope, 10000.0);
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  const int n = group(s, lines);
  const int paint = static_cast<int>(paint_y0s.size());
  if (!within_tilt) {
    EXPECT_EQ(n, paint) << "slope " << slope;
    return;
  }
  ASSERT_EQ(n, paint + 1) << "slope " << slope;
  const DetectedLine& row = lines[static_cast<std::size_t>(paint)];
  EXPECT_TRUE(row.parallel);
  EXPECT_TRUE(row.dots);
  EXPECT_EQ(row.marks, 5);
  EXPECT_NEAR(row.fit.m, slope, 1e-6);
  EXPECT_NEAR(row.fit.y_at(10000.0), y_ref, 0.1);
}

// Beside a single line, the road's direction is only as good as the detection pose's
// pitch: an error tilts a line 3.6 m from the one found by up to 3.6 m x tan(1.5 deg) /
// 1.2 m = 0.08 in slope. A row of dots so tilted, 200 mm across its 10 m (off the 100 mm
// y0 bins' edges), is found with its own slope.
TEST(LineGrouper, ARowOfDotsBesideOneLineMayRunAsAPitchErrorTiltsIt) {
  for (const double slope : {0.02, -0.02}) expect_tilted_dot_row({1800.0}, -1830.0, slope, true);
  expect_tilted_dot_row({1800.0}, -1830.0, 0.15, false);
}

// One lane beyond the lane's two lines, the road's direction is theirs extrapolated: a
// pitch error tilts it by up to 3.7 m x tan(1.5 deg) / 1.2 m = 0.08 in slope at 3.7 m
// from the outermost line. A row of dots so tilted, 250 mm across its 10 m (its votes
// along the road's direction within the 300 mm window a line beyond is looked for in), is
// found with its own slope.
TEST(LineGrouper, ARowOfDotsOneLaneBeyondMayRunAsAPitchErrorTiltsIt) {
  for (const double slope : {0.025, -0.025}) expect_tilted_dot_row({1800.0, -1800.0}, -5530.0, slope, true);
  expect_tilted_dot_row({1800.0, -1800.0}, -5530.0, 0.15, false);
}

// The same kind of row of blobs 2.6 m beyond the left line: a line of dots beyond white
// paint (the next lane's), none beyond a yellow edge line (a barrier's foot).
TEST(LineGrouper, NoRowOfDotsIsTakenBeyondAYellowEdgeLine) {
  for (const bool yellow : {false, true}) {
    Scene s;
    s.line(1800, 0.0, 0.0, 0.3, 1, yellow);
    s.line(-1800, 0.0, 0.0);
    s.dots(4400.0, 0.0);
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    const int n = group(s, lines);
    ASSERT_EQ(n, yellow ? 2 : 3) << "yellow " << yellow;
    if (!yellow) {
      EXPECT_NEAR(lines[0].fit.y0_mm, 4400.0, 1.0);
      EXPECT_TRUE(lines[0].dots);
    }
    EXPECT_NEAR(lines[n - 2].fit.y0_mm, 1800.0, 30.0);
    EXPECT_EQ(lines[n - 2].yellow, yellow);
  }
}

// A long row of blobs 2.6 m beyond the left line, one every 1.2 m from 5 to 40 m: enough
// for a line of its own from the vote, and for a prior to be continued by. Beyond white
// paint a line of dots (the next lane's), beyond a yellow edge line none, however it is
// found (segA's barrier foot, a line of its own in 119 of its 211 frames).
TEST(LineGrouper, NoLineOfDotsOfItsOwnIsTakenBeyondAYellowEdgeLine) {
  for (const bool tracked : {false, true})
    for (const bool yellow : {false, true}) {
      Scene s;
      s.line(1800, 0.0, 0.0, 0.3, 1, yellow);
      s.line(-1800, 0.0, 0.0);
      for (int row = 0; row < 150; row += 5) {
        MarkCandidate mk;
        mk.X = 5000.0 + 35000.0 * row / 149.0;
        mk.Y = 4400.0;
        mk.contrast = kPaintContrast;
        const double width_px = 630.0 * 100.0 / mk.X;
        mk.left_px = 600.0 - 0.5 * width_px;
        mk.right_px = 600.0 + 0.5 * width_px;
        mk.scan_row = static_cast<std::int16_t>(row);
        mk.dot = true;
        mk.dot_top = static_cast<std::int16_t>(row - 1);
        mk.dot_bottom = static_cast<std::int16_t>(row + 1);
        s.marks.push_back(mk);
      }
      std::vector<RoadLine> priors;
      if (tracked) priors = {RoadLine{4400.0, 0.0, 0.0}, RoadLine{1800.0, 0.0, 0.0}, RoadLine{-1800.0, 0.0, 0.0}};
      std::array<DetectedLine, kMaxDetectedLines> lines{};
      const int n = group(s, lines, priors);
      ASSERT_EQ(n, yellow ? 2 : 3) << "yellow " << yellow << " tracked " << tracked;
      if (!yellow) {
        EXPECT_NEAR(lines[0].fit.y0_mm, 4400.0, 30.0);
        EXPECT_TRUE(lines[0].dots);
      }
      EXPECT_EQ(lines[n - 2].yellow, yellow);
      int dots_on_lines = 0;
      for (const MarkCandidate& m : s.marks) dots_on_lines += m.dot && m.line >= 0;
      EXPECT_EQ(dots_on_lines > 0, !yellow) << "a dropped line's dots are freed";
    }
}

// An edge line beside a shoulder of another surface: every bar of it has a step beside
// it (for_lines_beyond). One lane beyond the road's two lines it is a line; such bars
// found no line of their own (beside a single line, or between the lane's lines), none
// beyond a yellow edge line, none where the own lane's line would be (the lines found
// both on the other side), and those no line took are left ungrouped.
TEST(LineGrouper, BarsWithAStepBesideMakeOnlyALineBeyondTheLane) {
  struct Case {
    const char* what;
    double held_y0;
    bool left_line, yellow_left;
    int want_lines;
    bool right_line = true;  // else a second line on the left, two lanes off
  };
  for (const Case& k :
       {Case{"beyond the right line", -5500.0, true, false, 3},
        Case{"beyond a yellow left line", 5400.0, true, true, 2}, Case{"inside the lane", 0.0, true, false, 2},
        Case{"beside one line alone", -5500.0, false, false, 1},
        Case{"as the own lane's right line", -1800.0, true, false, 2, false}}) {
    Scene s;
    if (k.left_line) s.line(1800, 0.01, 0.0, 0.3, 1, k.yellow_left);
    s.line(k.right_line ? -1800.0 : 5400.0, 0.01, 0.0);
    s.line(k.held_y0, 0.01, 0.0, 0.3, 1, false, true);
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    const int n = group(s, lines);
    ASSERT_EQ(n, k.want_lines) << k.what;
    int held_grouped = 0;
    for (const MarkCandidate& m : s.marks) held_grouped += m.for_lines_beyond && m.line >= 0;
    if (k.want_lines == 3) {
      EXPECT_NEAR(lines[2].fit.y0_mm, k.held_y0, 30.0) << k.what;
      EXPECT_NEAR(lines[2].fit.m, 0.01, 0.002) << k.what;  // the road's direction
      EXPECT_NEAR(held_grouped, 150, 10) << k.what;
    } else {
      EXPECT_EQ(held_grouped, 0) << k.what;
    }
  }
}

// A few dots found as a parallel of the lane's lines beyond one of them (a concrete's
// texture makes such rows) do not hide the line one lane beyond that line: the line
// beyond is looked for past the lane's line, and being paint, it takes the dots' place
// (TuSimple still 68: blobs 2.5 m beyond the left line, a double line 3.6 m beyond it,
// whose bars have a step beside them, the other stripe).
TEST(LineGrouper, AFewDotsBeyondTheLaneDoNotHideTheLineBeyondIt) {
  Scene s;
  s.line(1800, 0.01, 0.0);
  s.line(-1800, 0.01, 0.0);
  s.dots(4300.0 + 0.01 * 10000.0, 0.01);
  s.line(5400, 0.01, 0.0, 0.3, 1, false, true);
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines), 3);
  EXPECT_NEAR(lines[0].fit.y0_mm, 5400.0, 30.0);
  EXPECT_FALSE(lines[0].dots);
  EXPECT_NEAR(lines[1].fit.y0_mm, 1800.0, 30.0);
  EXPECT_NEAR(lines[2].fit.y0_mm, -1800.0, 30.0);
}

// A line beyond the lane is not held to the own lane's scatter: its direction is the
// road's as lines 3.5 m away give it, and its bars are mostly held ones, whose edges a
// step beside them pulls (TuSimple's shoulder lines: 1.2-1.4 px). Scattered about the
// line nearly as clutter in the gate is (evenly over +-2.2 px), it is found one lane
// beyond the lane; a line of the own lane scattered so is not.
TEST(LineGrouper, ALineBeyondTheLaneMayScatterMoreThanTheLanesOwn) {
  const auto scatter = [](Scene& s, std::size_t first) {
    std::uniform_real_distribution<double> px(-2.2, 2.2);
    for (std::size_t i = first; i < s.marks.size(); ++i) s.marks[i].Y += px(s.rng) * s.marks[i].X / 630.0;
  };
  {
    Scene s;
    s.line(1800, 0.01, 0.0);
    s.line(-1800, 0.01, 0.0);
    const std::size_t held = s.marks.size();
    s.line(-5500, 0.01, 0.0, 0.0, 1, false, true);
    scatter(s, held);
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    ASSERT_EQ(group(s, lines), 3);
    EXPECT_NEAR(lines[2].fit.y0_mm, -5500.0, 60.0);
  }
  {
    Scene s;
    s.line(1800, 0.01, 0.0);
    const std::size_t scattered = s.marks.size();
    s.line(-1800, 0.01, 0.0, 0.0);
    scatter(s, scattered);
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    ASSERT_EQ(group(s, lines), 1);
    EXPECT_NEAR(lines[0].fit.y0_mm, 1800.0, 30.0);
  }
}

// A line beyond the lane is continued only once both lines of the own lane were: on its
// own, its slope (here, as a dashed line's few bars may give it, 0.03 off the road's) became
// the road's direction the other lines were looked for along, and the own lane's left
// line, whose prior was lost, was refused as not running along it (segB, frame 103).
TEST(LineGrouper, ALineBeyondIsContinuedOnlyBesideTheOwnLane) {
  Scene s;
  s.line(1800, 0.01, 0.0);
  s.line(-1800, 0.01, 0.0);
  s.line(-5500, -0.02, 0.0, 0.3, 3);
  const std::array<RoadLine, 2> priors{RoadLine{-1800.0, 0.01, 0.0}, RoadLine{-5500.0, -0.02, 0.0}};
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  const int n = group(s, lines, priors);
  ASSERT_GE(n, 2);
  EXPECT_NEAR(lines[0].fit.y0_mm, 1800.0, 30.0);
  EXPECT_NEAR(lines[0].fit.m, 0.01, 0.002);
  EXPECT_GE(lines[0].marks, 140);
  EXPECT_NEAR(lines[1].fit.y0_mm, -1800.0, 30.0);
}

// Lanes are concrete slabs wide and their lines are set along the slabs' joints: where the
// own lane has a line on one side only, a joint a lane's width from it on the other side
// is the missing line, markers seen along it or not. A joint nearer than a lane's width
// (a slab's middle, a patch) is none, and with both own lines found no joint is looked for.
TEST(LineGrouper, AJointALanesWidthFromTheOwnLanesOnlyLineIsTheOtherLine) {
  struct Case {
    const char* what;
    double joint_y0;
    bool right_line;
    int want_lines;
  };
  for (const Case& k : {Case{"a lane's width from the left line", -1800.0, false, 2},
                        Case{"2.2 m from it", -400.0, false, 1}, Case{"beyond both lines", -5400.0, true, 2}}) {
    Scene s;
    s.line(1800, 0.01, 0.0);
    if (k.right_line) s.line(-1800, 0.01, 0.0);
    s.joint(k.joint_y0, 0.01);
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    const int n = group(s, lines);
    ASSERT_EQ(n, k.want_lines) << k.what;
    int joints_grouped = 0;
    for (const MarkCandidate& m : s.marks) joints_grouped += m.joint && m.line >= 0;
    if (!k.right_line && n == 2) {
      EXPECT_NEAR(lines[1].fit.y0_mm, k.joint_y0, 30.0) << k.what;
      EXPECT_NEAR(lines[1].fit.m, 0.01, 0.002) << k.what;
      EXPECT_FALSE(lines[1].dots) << k.what;
      EXPECT_GT(lines[1].joints, 140) << k.what;
    } else {
      EXPECT_EQ(joints_grouped, 0) << k.what;
    }
  }
}

// Blobs 100 mm beside that joint, all 6 px wide at every distance: three or more that keep
// their width so are no markers, and the dark line they lie along is a car's edge or a
// streak with lights on it, not a joint (no line). One or two give no width's slope at
// all, and say nothing either way: the joint is the other line, without them (TuSimple
// still 39, a joint with a marker or two beside it, lost its line whenever a third
// marker fell a level below the threshold).
TEST(LineGrouper, BlobsBesideAJointThatDoNotNarrowRefuseItOnlyWhenTheyAreEnoughToTell) {
  for (const int blobs : {1, 2, 3, 5}) {
    Scene s;
    s.line(1800, 0.01, 0.0);
    s.joint(-1800.0, 0.01);
    for (int k = 0; k < blobs; ++k) {
      MarkCandidate mk;
      mk.X = 15000.0 - 2500.0 * k;
      mk.Y = -1700.0 + 0.01 * mk.X;
      mk.contrast = kPaintContrast;
      mk.left_px = 597.0;
      mk.right_px = 603.0;
      mk.scan_row = static_cast<std::int16_t>(100 + 30 * k);
      mk.dot = true;
      mk.dot_top = static_cast<std::int16_t>(mk.scan_row - 1);
      mk.dot_bottom = static_cast<std::int16_t>(mk.scan_row + 1);
      s.marks.push_back(mk);
    }
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    const int n = group(s, lines);
    if (blobs < 3) {
      ASSERT_EQ(n, 2) << blobs << " blobs";
      EXPECT_NEAR(lines[1].fit.y0_mm, -1800.0, 30.0) << blobs << " blobs";
      EXPECT_FALSE(lines[1].dots) << blobs << " blobs";
      EXPECT_GT(lines[1].joints, 140) << blobs << " blobs";
      for (const MarkCandidate& m : s.marks) EXPECT_FALSE(m.dot && m.line >= 0) << blobs << " blobs";
    } else {
      EXPECT_EQ(n, 1) << blobs << " blobs";
    }
  }
}

// A joint's scatter is the joint's, on the road: a camera with more pixels across the
// same view sees it over more pixels. A row of markers along a joint that meanders by
// 1.84 pixels of a 1150 px focal length (an rms of 1.3, over the fit's 1.1) is refused
// at that focal length. At 1725 px (a 1920 wide picture of the same view) the joint
// that meanders by 1.84 of those pixels, 1.23 of the reference's, is the markers' line,
// as it is at 1150 px; and so at 630 px, where the scatter is judged in the camera's
// own, coarser pixels.
TEST(LineGrouper, AJointsScatterIsJudgedInTheViewNotInTheCamerasPixels) {
  struct Case {
    const char* what;
    double focal_px, meander_px, meander_focal_px;
    bool joined;
  };
  for (const Case& k :
       {Case{"1.84 px at 1150 px", 1150.0, 1.84, 1150.0, false}, Case{"1.84 px at 1725 px", 1725.0, 1.84, 1725.0, true},
        Case{"1.23 px at 1150 px", 1150.0, 1.23, 1150.0, true}, Case{"1.23 px at 630 px", 630.0, 1.23, 630.0, true},
        Case{"1.84 px of 1150 at 1725 px", 1725.0, 1.84, 1150.0, false}}) {
    Scene s;
    s.joint(-1800.0, 0.01, k.meander_px / k.meander_focal_px);
    s.dots(-1800.0, 0.01);
    LineGrouper g(4096);
    GroupingParams p;
    p.mm_per_px_per_mm = 1.0 / k.focal_px;
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    const int n = g.group(s.marks, {}, p, lines);
    int joined = 0;
    for (int j = 0; j < n; ++j) joined += lines[j].joints > 100 && std::abs(lines[j].fit.y0_mm + 1800.0) < 30.0;
    EXPECT_EQ(joined, k.joined ? 1 : 0) << k.what;
  }
}

// The previous frame's line along a slabs' joint with three markers on it, where the
// frame shows it alone (the lane's other line hidden) and five blobs (a patch's stains)
// run 400 mm beside it, within the prior's gate: looked for as paint, the gated marks'
// consensus is the blobs' row (the joint's pieces are no paint), too few dots for a line,
// and the joint looked for about that row is not there. Looked for about the prior, the
// joint is the line, its markers on it (held still 3: a line of 57 pieces and 3 markers
// lost so). A joint without markers is a seam, and no line.
TEST(LineGrouper, APriorAlongAJointWithMarkersIsContinuedByItsJoint) {
  const std::array<RoadLine, 2> priors{RoadLine{1800.0, 0.01, 0.0}, RoadLine{-1800.0, 0.01, 0.0}};
  for (const bool markers : {true, false}) {
    Scene s;
    s.joint(-1800.0, 0.01);
    s.dots(-1400.0, 0.01);
    if (markers) {
      const std::size_t blobs = s.marks.size();
      s.dots(-1800.0, 0.01);
      // Three of the five, 5 m apart (15, 10 and 5 m ahead).
      s.marks.erase(s.marks.begin() + static_cast<std::ptrdiff_t>(blobs) + 3);
      s.marks.erase(s.marks.begin() + static_cast<std::ptrdiff_t>(blobs) + 1);
    }
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    const int n = group(s, lines, priors);
    int on_joint = 0;
    for (int j = 0; j < n; ++j) on_joint += std::abs(lines[j].fit.y0_mm + 1800.0) < 30.0;
    if (!markers) {
      EXPECT_EQ(on_joint, 0) << "a bare joint";
      continue;
    }
    ASSERT_EQ(n, 1);
    EXPECT_EQ(lines[0].prior_index, 1);
    EXPECT_NEAR(lines[0].fit.y0_mm, -1800.0, 30.0);
    EXPECT_NEAR(lines[0].fit.m, 0.01, 0.002);
    EXPECT_GT(lines[0].joints, 140);
    EXPECT_TRUE(lines[0].dots);
  }
}

// The previous frame's line with, 600 mm beside it over the nearest 8 m, a run of bars
// too near it to be a lane line (a gore's edge, a barrier's foot, a seam): the run is
// refused. Near marks vote for the same y0 at every slope, so its marks, were they left
// free, would win cell after cell and use up the attempts for new lines; the dashed
// line on the other side must still be found.
TEST(LineGrouper, ARunRefusedBesideALineDoesNotHideTheRoadsOtherLines) {
  Scene s;
  s.line(1800, 0.0, 0.0);
  for (int row = 0; row < 240; ++row) {  // a mark on every row: near rows are dense
    MarkCandidate mk;
    mk.contrast = kPaintContrast;
    mk.X = 12000.0 - 8000.0 * row / 239.0;
    mk.Y = 2400.0;
    mk.scan_row = static_cast<std::int16_t>(150 + row);
    s.marks.push_back(mk);
  }
  // Tilted by a pitch error (by 3.6 m x 1 degree / 1.2 m): the road's direction the
  // first line gives misses its far end.
  s.line(-2300, 0.05, 0.0, 0.3, 4);
  const RoadLine prior[] = {{1800, 0, 0}};
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines, prior), 2);
  EXPECT_NEAR(lines[0].fit.y0_mm, 1800.0, 30.0);
  EXPECT_NEAR(lines[1].fit.y0_mm, -2300.0, 30.0);
  EXPECT_NEAR(lines[1].fit.m, 0.05, 0.002);
  EXPECT_FALSE(lines[1].parallel);
  // The refused run's marks are free again once grouping ends.
  for (const MarkCandidate& m : s.marks) EXPECT_GE(m.line, -1);
}

// Beside the own lane's two lines, a car's lower edge seen from behind makes a dense run
// of bars over 12 m of road that, projected at the pose, slants 0.12 off the road's
// direction: the lines of a road meet at one vanishing point, and it is no lane line.
// Along the road, the same run is a line.
TEST(LineGrouper, ALineSlantedAcrossTheRoadsDirectionIsNoLaneLine) {
  for (const double slant : {0.12, 0.0}) {
    Scene s;
    s.line(1800, 0.0, 0.0);
    s.line(-1800, 0.0, 0.0);
    for (int row = 0; row < 60; ++row) {
      const double X = 20000.0 - 12000.0 * row / 59.0;
      MarkCandidate mk;
      mk.contrast = kPaintContrast;
      mk.X = X;
      mk.Y = -5400.0 + slant * (X - 8000.0);
      mk.scan_row = static_cast<std::int16_t>(60 + row);
      s.marks.push_back(mk);
    }
    std::array<DetectedLine, kMaxDetectedLines> lines{};
    EXPECT_EQ(group(s, lines), slant == 0.0 ? 3 : 2) << "slant " << slant;
  }
}

TEST(LineGrouper, KeepsTheNearestLinesAndMergesNeighbours) {
  Scene s;
  for (double y0 : {9000.0, 5000.0, 1800.0, -1800.0, -5800.0}) s.line(y0, 0.0, 0.0);
  s.line(-1200, 0.0, 0.0, 0.3, 3);  // 0.6 m from a stronger line: one line, not two
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  ASSERT_EQ(group(s, lines, {}, 3), 3);
  EXPECT_NEAR(lines[0].fit.y0_mm, 5000, 50);
  EXPECT_NEAR(lines[1].fit.y0_mm, 1800, 50);
  EXPECT_LT(lines[2].fit.y0_mm, -1000);
  EXPECT_GT(lines[2].fit.y0_mm, -2000);
}

TEST(LineGrouper, SparseClutterIsNoLine) {
  Scene s;
  s.clutter(400);
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  EXPECT_EQ(group(s, lines), 0);
}

TEST(LineGrouper, GroupingAllocatesNothing) {
  Scene s;
  s.line(1800, 0.0, 0.0);
  s.line(-1800, 0.0, 0.0);
  s.clutter(200);
  LineGrouper g(4096);
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  const RoadLine priors[] = {{1800, 0, 0}};
  test::AllocationScope scope;
  EXPECT_EQ(g.group(s.marks, priors, GroupingParams{}, lines), 2);
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace ccdlane
