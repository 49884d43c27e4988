// The shadowed-dot pass of the row filter on rows with exactly known markers: a lit cap
// beside its shadow is found, centred on the edge between them, either way round; what
// only looks like one in part (a cap or a shadow alone, a shadow's border, a marker too
// wide, a pair on rough texture, a cap the bar pass already holds) is not.
#include "core/detection/dot_scanner.hpp"

#include <gtest/gtest.h>

#include "tests/core/detection/row_fixture.hpp"

namespace ccdlane {
namespace {

using test::Row;
using test::scan;

// A row where paint is 12 px wide (its narrowest 3.8 px) and a marker 6 px.
ScanRow dot_row() {
  ScanRow r = test::row_for(12.0f);
  r.dot_px = 6.0f;
  return r;
}

// Road at 80; the marker's cap from `cap` to `edge` at `lit`, its shadow from `edge` to
// `end` at `dark` (cap left of the shadow when cap < edge).
Row marker(double cap, double edge, double end, double lit = 150.0, double dark = 30.0) {
  Row row;
  row.bar(std::min(cap, edge), std::max(cap, edge), lit);
  row.bar(std::min(edge, end), std::max(edge, end), dark);
  return row;
}

TEST(DotScanner, FindsALitCapBesideItsShadowCentredOnTheEdgeBetween) {
  for (const double edge : {62.5, 62.8, 63.1}) {
    for (const int side : {+1, -1}) {  // the shadow right of the cap, then left
      const Row row = marker(edge - side * 2.5, edge, edge + side * 7.0);
      const auto c = scan(row.bytes8(), dot_row());
      ASSERT_EQ(c.size(), 1u) << edge << " side " << side;
      // The edge is where the row crosses the middle level; 1-based columns: + 1. An
      // edge within a pixel is interpolated linearly between its neighbours, to a
      // quarter pixel.
      EXPECT_NEAR(c[0].px(), edge + 1.0, 0.25) << edge << " side " << side;
      EXPECT_EQ(c[0].shadow_side, side);
      EXPECT_TRUE(c[0].narrow) << "a candidate only as a dot";
      EXPECT_NEAR(c[0].width_px(), 2 * 3.0, 2.01) << "two caps: the dome";
      EXPECT_NEAR(c[0].shadow_px, 7.0, 1.01);
      EXPECT_GT(c[0].contrast, 30.0);
    }
  }
  ScanRow no_dots = dot_row();
  no_dots.dot_px = 0.0f;
  EXPECT_TRUE(scan(marker(60.0, 62.5, 69.5).bytes8(), no_dots).empty()) << "the cap alone is narrower than paint";
}

TEST(DotScanner, WhatIsOnlyPartOfALitMarkerIsNone) {
  Row cap, shadow, border, pole, dim;
  cap.bar(60.0, 62.5, 150.0);     // no shadow: a speck, a reflection
  shadow.bar(60.0, 67.0, 30.0);   // no cap: an oil drop, a pothole
  border.bar(60.0, 62.5, 150.0);  // a lit edge on the border of a shadow over the road
  border.bar(62.5, 140.0, 30.0);
  pole = marker(60.0, 62.5, 86.5);             // a shadow 4 markers long: a pole's, beside a speck
  dim = marker(60.0, 62.5, 69.5, 86.0, 74.0);  // 6 levels each way: below the contrast asked
  for (const Row* r : {&cap, &shadow, &border, &pole, &dim}) EXPECT_TRUE(scan(r->bytes8(), dot_row()).empty());
  Row shaded_side = marker(60.0, 62.5, 69.5);  // the road beyond the shadow is in shade too
  shaded_side.bar(69.5, 140.0, 40.0);
  EXPECT_TRUE(scan(shaded_side.bytes8(), dot_row()).empty());
}

TEST(DotScanner, AMarkerStandsOutOfSmoothRoadNotOfRoughTexture) {
  // Cap and shadow 30 levels from the road. With noise of 1 level the road is smooth
  // beside them; with 25, its mean deviation (20) is twice the 30 % of 30 a marker's
  // neighbourhood may have: the same marker is no longer one, but where the noise lifts
  // its contrast too (one draw in 50 here; without the test, most). Noise makes pairs of
  // its own elsewhere on such a row, which the detector's checks in two dimensions meet.
  int smooth = 0, rough = 0;
  for (unsigned seed = 0; seed < 50; ++seed) {
    Row a = marker(60.0, 62.5, 69.5, 110.0, 50.0), b = a;
    a.noise(1.0, seed);
    b.noise(25.0, seed);
    smooth += scan(a.bytes8(), dot_row()).size() == 1;
    for (const MarkCandidate& c : scan(b.bytes8(), dot_row()))
      rough += c.shadow_side != 0 && std::abs(c.px() - 63.5) < 4;
  }
  EXPECT_EQ(smooth, 50);
  EXPECT_LE(rough, 2);
}

TEST(DotScanner, ACapTheBarPassFindsIsNotFoundTwice) {
  // Where paint may be 4 px wide (its narrowest 0.8 px) the cap is a bar of its own.
  ScanRow r = test::row_for(4.0f);
  r.dot_px = 6.0f;
  const auto c = scan(marker(60.0, 63.0, 70.0).bytes8(), r);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].shadow_side, 0);
}

}  // namespace
}  // namespace ccdlane
