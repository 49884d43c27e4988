// The row filter on rows with exactly known bars: sub-pixel centres, what is and is not
// a dark-bright-dark bar of the expected width, both pixel depths, no allocation.
#include "core/detection/mark_scanner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/core/detection/row_fixture.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

using test::Row;
using test::row_for;
using test::scan;

TEST(MarkScanner, FindsBarsWithSubPixelCentresAndWidths) {
  for (const double width : {1.7, 3.0, 6.4, 12.0}) {
    for (const double start : {40.0, 40.25, 40.5, 40.8}) {
      Row row;
      row.bar(start, start + width, 200.0);
      row.bar(150.3, 150.3 + width, 180.0);
      const auto c = scan(row.bytes8(), row_for(static_cast<float>(width)));
      ASSERT_EQ(c.size(), 2u) << width << " at " << start;
      // 0-based continuous centre -> 1-based pixel index: + 1.
      EXPECT_NEAR(c[0].px(), start + width / 2 + 1.0, 0.06) << width << " at " << start;
      EXPECT_NEAR(c[0].width_px(), width, 0.5) << width;
      EXPECT_NEAR(c[1].px(), 150.3 + width / 2 + 1.0, 0.06) << width;
      EXPECT_EQ(c[0].py, 2.0);
      EXPECT_NEAR(c[0].contrast, 120.0, width < 2 ? 60.0 : 25.0);
    }
  }
}

TEST(MarkScanner, NoiseOfOneGreyLevelMovesCentresByHundredths) {
  double sum2 = 0;
  int n = 0;
  for (unsigned seed = 0; seed < 200; ++seed) {
    Row row;
    const double start = 60.0 + 0.01 * seed;
    row.bar(start, start + 4.0, 190.0);
    row.noise(1.0, seed);
    const auto c = scan(row.bytes8(), row_for(4.0f));
    ASSERT_EQ(c.size(), 1u) << seed;
    sum2 += std::pow(c[0].px() - (start + 3.0), 2);
    ++n;
  }
  EXPECT_LT(std::sqrt(sum2 / n), 0.05);
}

TEST(MarkScanner, RejectsWhatIsNotAMarkOfThisWidth) {
  Row wide, step, faint, bright_side, dark_bar;
  wide.bar(50, 50 + 30, 200);    // a car or a patch: 7.5 x the expected 4 px
  step.bar(100, 200, 200);       // an edge, no far side
  faint.bar(50, 54, 86);         // 6 grey levels: below the contrast asked
  bright_side.bar(50, 54, 150);  // a stair up to a brighter area: not dark-bright-dark
  bright_side.bar(54, 90, 220);
  dark_bar.bar(50, 54, 20);  // a dark bar (a crack, a tar seam)
  for (const Row* r : {&wide, &step, &faint, &bright_side, &dark_bar})
    EXPECT_TRUE(scan(r->bytes8(), row_for(4.0f)).empty());
  Row narrow;
  narrow.bar(50, 50.6, 250);  // far narrower than a mark of 8 px
  EXPECT_TRUE(scan(narrow.bytes8(), row_for(8.0f)).empty());
}

TEST(MarkScanner, BarsNarrowerThanPaintAreKeptFlaggedWhereADotMayBe) {
  // The lit cap of a raised marker: 2 px where paint would be 8 px wide (min 2.2 px).
  Row cap, paint;
  cap.bar(50, 52.0, 200);
  paint.bar(50, 58, 200);
  ScanRow r = row_for(8.0f);
  EXPECT_TRUE(scan(cap.bytes8(), r).empty()) << "no dots asked for: paint's widths only";
  r.min_dot_width_px = 1.5f;
  const auto c = scan(cap.bytes8(), r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_TRUE(c[0].narrow);
  EXPECT_NEAR(c[0].px(), 51.0 + 1.0, 0.3);  // 1-based columns
  const auto p = scan(paint.bytes8(), r);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_FALSE(p[0].narrow);
  Row hair;
  hair.bar(50, 50.7, 250);  // a pixel's line: narrower than a dot's cap
  EXPECT_TRUE(scan(hair.bytes8(), r).empty());
}

TEST(MarkScanner, JointsAreDarkLinesBetweenSidesOfOneLevel) {
  // The sealed joint between two slabs, 2 px wide and 40 levels below the road, where a
  // mark is 8 px: its centre to a fraction of a pixel.
  Row joint;
  joint.bar(100.2, 102.2, 40);
  ScanRow r = row_for(8.0f);
  EXPECT_TRUE(scan(joint.bytes8(), r).empty()) << "no joints asked for on this row";
  r.max_joint_px = 4.0f;
  const auto c = scan(joint.bytes8(), r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_TRUE(c[0].joint);
  EXPECT_NEAR(c[0].px(), 101.2 + 1.0, 0.25);  // 1-based columns
  EXPECT_NEAR(c[0].contrast, 40.0, 4.0);
  // Not joints: a shadow's border (a step down, no far side), a dark patch wider than a
  // joint, a line too faint, and a dark line along a step (its sides differ by more than
  // half its depth: a patch's edge).
  Row step, patch, faint, edge;
  step.bar(100, 200, 40);
  patch.bar(100, 112, 40);
  faint.bar(100.2, 102.2, 74);
  edge.bar(102.2, 200, 60);
  edge.bar(100.2, 102.2, 40);
  for (const Row* row : {&step, &patch, &faint, &edge}) {
    const auto none = scan(row->bytes8(), r);
    EXPECT_TRUE(std::none_of(none.begin(), none.end(), [](const MarkCandidate& m) { return m.joint; }));
  }
}

// Contrast markings: white paint between black borders on pale concrete. The borders are
// steps within the derivative's reach on both sides, alike, so they pull the bar's edges
// alike and its centre stays put: no step beside it where the row asks for borders this
// wide (ScanRow::min_border_px). A one-sided dark band, thin dark lines (joints beside a
// marker's cap) or shallow ones are steps that bias a bar.
TEST(MarkScanner, PaintBetweenBlackBordersIsNoBarBesideAStep) {
  constexpr double kConcrete = 170.0;
  const auto on_concrete = [](std::initializer_list<std::array<double, 3>> bands) {
    Row row;
    row.bar(0, 200, kConcrete);
    for (const auto& [left, right, level] : bands) row.bar(left, right, level - kConcrete + 80.0);  // set, not add
    return row;
  };
  const Row bordered = on_concrete({{94.3, 100.3, 30}, {100.3, 108.3, 200}, {108.3, 114.3, 30}});
  const Row left_only = on_concrete({{94.3, 100.3, 30}, {100.3, 108.3, 200}});
  const Row joints = on_concrete({{98.3, 100.3, 30}, {100.3, 108.3, 200}, {108.3, 110.3, 30}});
  const Row shallow = on_concrete({{94.3, 100.3, 150}, {100.3, 108.3, 200}, {108.3, 114.3, 150}});
  ScanRow r = row_for(8.0f);
  const auto one_bar = [&](const Row& row) {
    const auto c = scan(row.bytes8(), r);
    EXPECT_EQ(c.size(), 1u);
    return c.empty() ? MarkCandidate{} : c[0];
  };
  EXPECT_TRUE(one_bar(bordered).step_beside) << "no borders asked for on this row";
  r.min_border_px = 4.0f;
  const MarkCandidate paint = one_bar(bordered);
  EXPECT_FALSE(paint.step_beside);
  EXPECT_NEAR(paint.px(), 104.3 + 1.0, 0.1);  // 1-based columns
  for (const Row* row : {&left_only, &joints, &shallow}) EXPECT_TRUE(one_bar(*row).step_beside);
}

// A blurred picture's edges ramp over more pixels than the step test's window allows
// for: the ramp is no step, and the bars' centres are unbiased (it is the same on both
// sides). The scanner measures the blur from its clear bars' edges (contrast over the
// steepest one-pixel rise, sigma sqrt(2 pi) for a Gaussian-blurred step), here a near
// dash's 16 px, and reads the step test past the ramp; a picture as sharp as a camera's
// own edges keeps it at the edge, and a real step beside a blurred bar is still one.
TEST(MarkScanner, ABlurredEdgesRampIsNoStepBesideIt) {
  // The blurred picture's sigma, 2.2 px, measures about 2.1 (a near dash's inside mean
  // is a little below its plateau): one pixel past the edge, 1.5 x (2.1 - 1.36). A
  // shadow's border 5 px past a far bar's edge lies inside the window read there (h = 2:
  // pixels 3-6 past it).
  constexpr double kSigmaPx = 2.2, kShadowPx = 5.0;
  struct Scanned {
    std::vector<MarkCandidate> far;  // the 5 px bars' (every other row)
    int offset = -1;
  };
  const auto scan_rows = [&](double sigma, bool shadow_beside) {
    MarkScanner scanner(200);
    std::vector<MarkCandidate> out(64);
    scanner.clear_edges();
    Scanned s;
    for (int k = 0; k < 12; ++k) {  // rows of one picture: near and far bars, at other sub-pixel places
      const bool near = k % 2 == 0;
      const double width = near ? 16.0 : 5.0, left = 60.0 + 0.17 * k;
      Row row;
      row.bar(left, left + width, 200.0);
      if (shadow_beside && !near) row.bar(left + width + kShadowPx, 200.0, 20.0);  // the road darker from there
      row.blur(sigma);
      const std::vector<std::uint8_t> pixels = row.bytes8();
      const int n = scanner.scan(ImageView{pixels.data(), 200, 3, 200, PixelFormat::mono8, 8},
                                 row_for(near ? 16.0f : 4.0f), k, 10.0f, 1.0f, out.data(), 0, 64);
      if (!near && n == 1) s.far.push_back(out[0]);
    }
    s.offset = scanner.step_window_offset();
    return s;
  };
  const Scanned sharp = scan_rows(0.7, false), blurred = scan_rows(kSigmaPx, false),
                shadowed = scan_rows(kSigmaPx, true);
  ASSERT_EQ(sharp.far.size(), 6u);
  ASSERT_EQ(blurred.far.size(), 6u);
  ASSERT_EQ(shadowed.far.size(), 6u);
  EXPECT_EQ(sharp.offset, 0);
  EXPECT_EQ(blurred.offset, 1);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_FALSE(sharp.far[i].step_beside) << i;
    EXPECT_TRUE(blurred.far[i].step_beside_at & 1) << i << ": the ramp reaches the window at the edge";
    EXPECT_FALSE((blurred.far[i].step_beside_at >> blurred.offset) & 1) << i;
    EXPECT_NEAR(blurred.far[i].px(), 62.5 + 0.17 * static_cast<double>(2 * i + 1) + 1.0, 0.1) << i;
    EXPECT_TRUE((shadowed.far[i].step_beside_at >> blurred.offset) & 1) << i << ": a shadow's border is a step";
  }
}

TEST(MarkScanner, SixteenBitRowsGiveTheSameBars) {
  Row row;
  row.bar(70.4, 75.9, 210);
  row.noise(0.5, 3);
  const auto b8 = row.bytes8();
  std::vector<std::uint16_t> b16(600);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 200; ++x)
      b16[static_cast<std::size_t>(y * 200 + x)] =
          static_cast<std::uint16_t>(std::lround(row.value[static_cast<std::size_t>(x)] * 4095.0 / 255.0));
  MarkScanner s(200);
  std::vector<MarkCandidate> out(8);
  const float scale = 4095.0f / 255.0f;
  const int n =
      s.scan(ImageView{reinterpret_cast<const std::uint8_t*>(b16.data()), 200, 3, 400, PixelFormat::mono16, 12},
             row_for(5.5f), 0, 10 * scale, 1 / scale, out.data(), 0, 8);
  ASSERT_EQ(n, 1);
  const auto c8 = scan(b8, row_for(5.5f));
  ASSERT_EQ(c8.size(), 1u);
  EXPECT_NEAR(out[0].px(), c8[0].px(), 0.05);
  EXPECT_NEAR(out[0].contrast, c8[0].contrast, 1.0);
}

TEST(MarkScanner, StopsAtCapacityAndAllocatesNothing) {
  Row row;
  for (int k = 0; k < 10; ++k) row.bar(10 + 18 * k, 14 + 18 * k, 200);
  const auto img = row.bytes8();
  MarkScanner s(200);
  std::vector<MarkCandidate> out(4);
  const ImageView view{img.data(), 200, 3, 200, PixelFormat::mono8, 8};
  test::AllocationScope scope;
  const int n = s.scan(view, row_for(4.0f), 0, 10, 1.0f, out.data(), 1, 4);
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(n, 4);  // 3 appended after the one already there
  EXPECT_NEAR(out[1].px(), 13.0, 0.05);
}

}  // namespace
}  // namespace ccdlane
