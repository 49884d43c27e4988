// The own lane's other line looked for along its length in the picture: found from a few
// markers a lane's width from the line beside it, where it is; never in speckled concrete,
// along a step, or at the end of the widths looked at. And the next lane's line beyond
// the own lane's, looked for the same way.
#include "core/detection/line_in_picture.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/lane_detector.hpp"
#include "tests/core/detection/marker_drawing.hpp"

namespace ccdlane {
namespace {

using test::draw_band;
using test::draw_dot;
using test::TuSimpleConcreteRoad;

constexpr double kLeftLineY = 1800.0, kLaneWidthMm = 3650.0, kDotsY = kLeftLineY - kLaneWidthMm;
constexpr double kMinContrast = 10.0;  // DetectionConfig's min_contrast, 8-bit frames
// A row of markers with most of them missing: five, 4-9 m apart (worn off, hidden by the
// traffic ahead), each too few on its own for the grouping's lines.
constexpr double kDotsX[] = {6000.0, 11500.0, 17000.0, 24000.0, 33000.0};

// Concrete's aggregate: bright specks a pixel or two across, 20-40 levels above it,
// scattered over the road as they are over real slabs.
void speckle(const MutableImageView& im, std::uint32_t seed, int count) {
  for (int i = 0; i < count; ++i) {
    seed = seed * 1664525u + 1013904223u;
    const int x = static_cast<int>((seed >> 8) % static_cast<std::uint32_t>(im.width - 2));
    seed = seed * 1664525u + 1013904223u;
    const int y = static_cast<int>(im.height / 3 + (seed >> 8) % static_cast<std::uint32_t>(2 * im.height / 3 - 1));
    const auto lift = static_cast<std::uint8_t>(170 + (seed >> 28) * 2);
    im.row(y)[x] = lift;
    if (seed & 1u) im.row(y)[x + 1] = lift;
  }
}

const RoadLine kLeftLine{kLeftLineY, 0.0, 0.0};

// The right-hand line of the lane whose left line is kLeftLine, over 3-40 m.
const PictureLine& look_right(PictureLineSearch& search, const TuSimpleConcreteRoad& road,
                              ChanceRule chance = ChanceRule::clean_road) {
  return search.find(road.frame.view, road.pose, kLeftLine, -4800.0, -2600.0, 3000.0, 40000.0, 130.0, kMinContrast,
                     chance);
}

TEST(PictureLineSearch, AFewMarkersALanesWidthFromTheLineFoundAreItsOtherLine) {
  TuSimpleConcreteRoad road(3);
  speckle(road.frame.view, 11, 300);
  for (const double X : kDotsX) draw_dot(road.frame.view, road.ground, road.model, X, kDotsY, 230);
  PictureLineSearch search(road.c.camera);
  const PictureLine& l = look_right(search, road);
  ASSERT_TRUE(l.found) << l.hits << " hits in " << l.groups << " places, " << l.pieces << " pieces, chance "
                       << l.baseline;
  // At the markers' offset to within a candidate step (the markers' pixels are rounded).
  EXPECT_NEAR(l.offset_mm, kDotsY - kLeftLineY, PictureLineSearch::kOffsetStepMm);
  // Four of the five markers are hit (the farthest, 33 m off, covers a fifth of a row),
  // and every hit lies on the line: within half a step and a pixel of it (a speck there
  // is a hit too; the solve's fit takes it as one more pick within its noise).
  int markers_hit = 0;
  for (const double X : kDotsX) {
    bool hit = false;
    for (const PictureLineHit& h : l.marks) hit |= std::abs(h.X - X) < test::kDotRadiusMm + h.X / 200.0;
    markers_hit += hit;
  }
  EXPECT_GE(markers_hit, 4);
  for (const PictureLineHit& h : l.marks)
    EXPECT_NEAR(h.Y, kDotsY, 0.5 * PictureLineSearch::kOffsetStepMm + h.X / 150.0) << "a hit at " << h.X << " mm";
}

TEST(PictureLineSearch, DotsFourFeetApartAreSeparatePlacesSeenFromAPoseTooLow) {
  // Caltrans' pattern: groups of four Botts' dots 1.22 m apart, repeating every 14.6 m.
  // Looked for from a pose 25 % too low (a search's guessed height), which measures the
  // road 0.75 times as long and as wide: the dots are 0.92 m apart as it sees them, and
  // still each a place of its own.
  TuSimpleConcreteRoad road(3);
  speckle(road.frame.view, 11, 300);
  std::vector<double> dots_x;
  for (double group = 5000.0; group < 40000.0; group += 14630.0)
    for (int k = 0; k < 4; ++k) dots_x.push_back(group + 1220.0 * k);
  for (const double X : dots_x) draw_dot(road.frame.view, road.ground, road.model, X, kDotsY, 230);
  CameraPose low = road.pose;
  low.H_mm *= 0.75;
  const RoadLine left_seen_low{0.75 * kLeftLineY, 0.0, 0.0};
  PictureLineSearch search(road.c.camera);
  const PictureLine& l =
      search.find(road.frame.view, low, left_seen_low, -4800.0, -2600.0, 3000.0, 40000.0, 130.0, kMinContrast);
  ASSERT_TRUE(l.found) << l.hits << " hits in " << l.groups << " places, " << l.pieces << " pieces";
  EXPECT_NEAR(l.offset_mm, 0.75 * (kDotsY - kLeftLineY), 2.0 * PictureLineSearch::kOffsetStepMm);
  EXPECT_GE(l.groups, 8);  // of the 12 dots, those in view and hit
}

TEST(PictureLineSearch, SpeckledConcreteHasNoLine) {
  // Specks pile up on every candidate alike: none stands out by five of chance's standard
  // deviations, by either rule. Twenty textures, as dense as the aggregate of a pale slab.
  for (const ChanceRule chance : {ChanceRule::clean_road, ChanceRule::any_road}) {
    int found = 0;
    for (std::uint32_t seed = 1; seed <= 20; ++seed) {
      TuSimpleConcreteRoad road(seed);
      speckle(road.frame.view, seed * 7919u, 6000);
      PictureLineSearch search(road.c.camera);
      found += look_right(search, road, chance).found;
    }
    EXPECT_EQ(found, 0) << (chance == ChanceRule::clean_road ? "clean road" : "any road");
  }
}

TEST(PictureLineSearch, OnATexturedRoadALineIsTakenOnlyByTheAnyRoadRule) {
  // Concrete whose specks put several hits on the median candidate, and a row of markers:
  // the clean road's rule refuses what the texture's spread alone would take.
  TuSimpleConcreteRoad road(5);
  speckle(road.frame.view, 5 * 7919u, 2000);
  for (double X = 6000.0; X <= 36000.0; X += 2500.0) draw_dot(road.frame.view, road.ground, road.model, X, kDotsY, 230);
  PictureLineSearch search(road.c.camera);
  const PictureLine& clean = look_right(search, road, ChanceRule::clean_road);
  EXPECT_GT(clean.baseline, PictureLineSearch::kMaxChanceHits);
  EXPECT_FALSE(clean.found);
  const PictureLine& any = look_right(search, road, ChanceRule::any_road);
  ASSERT_TRUE(any.found) << any.hits << " hits, chance " << any.baseline << " +- " << any.spread;
  // Within two steps: far off, where a step is under a pixel, neighbouring candidates
  // read the same markers, and a speck beside one decides between them.
  EXPECT_NEAR(any.offset_mm, kDotsY - kLeftLineY, 2.0 * PictureLineSearch::kOffsetStepMm);
}

TEST(PictureLineSearch, TwoWornDashesSeenAlongTheirLengthAreALineBeyondALane) {
  // Two dashes of a dashed line (3 m long, 9 m apart) and nothing else of it: a car hides
  // the rest, or the picture's edge cuts it off. Each is worn through for 0.4 m (a joint
  // across it), so each is one place along the road and two pieces in the picture. Two or
  // three places are fewer than a row of dots needs; seen along their length, as dashes,
  // they are a line beyond a lane found (the next lane's), not the own lane's other line,
  // which a clean road's rule looks for.
  for (const bool worn : {true, false}) {
    TuSimpleConcreteRoad road(3);
    speckle(road.frame.view, 11, 300);
    for (const double X : {9000.0, 21000.0}) {
      const double gap = worn ? 400.0 : 0.0;
      draw_band(road.frame.view, road.ground, road.model, kDotsY, X, X + 1300.0, 130.0, 230);
      draw_band(road.frame.view, road.ground, road.model, kDotsY, X + 1300.0 + gap, X + 3000.0, 130.0, 230);
    }
    PictureLineSearch search(road.c.camera);
    const PictureLine& any = look_right(search, road, ChanceRule::any_road);
    EXPECT_LT(any.groups, PictureLineSearch::kMinGroups) << worn;
    EXPECT_EQ(any.dashes, 2) << worn;
    if (!worn) {
      // Two unbroken runs are two pieces: as many as the side skirts of two trucks in the
      // next lane would make, which a line needs kMinPieces more than.
      EXPECT_LT(any.pieces, PictureLineSearch::kMinPieces);
      EXPECT_FALSE(any.found);
      continue;
    }
    ASSERT_TRUE(any.found) << any.hits << " hits in " << any.groups << " places, " << any.pieces << " pieces";
    EXPECT_NEAR(any.offset_mm, kDotsY - kLeftLineY, PictureLineSearch::kOffsetStepMm);
    EXPECT_FALSE(look_right(search, road, ChanceRule::clean_road).found);
  }
}

TEST(PictureLineSearch, AStepAlongTheRoadIsNoLine) {
  // A shoulder of brighter concrete beyond the lane's edge, 50 levels up: bright on one
  // side only, a shadow's border or a kerb looks the same.
  TuSimpleConcreteRoad road(4);
  for (int y = 0; y < road.frame.view.height; ++y)
    for (int x = 0; x < road.frame.view.width; ++x) {
      double X = 0, Y = 0;
      if (road.ground.ground(x + 1.0, y + 1.0, X, Y) && Y < kDotsY) road.frame.view.row(y)[x] = 200;
    }
  PictureLineSearch search(road.c.camera);
  EXPECT_FALSE(look_right(search, road).found);
}

TEST(PictureLineSearch, ALineAtTheEndOfTheWidthsLookedAtIsNotTaken) {
  // The markers 4.82 m from the line found: the widest candidate's hits peak at the end of
  // the widths looked at, where a line nearer or farther would peak too (the next lane's
  // line, or a wide lane's); it is not taken for this lane's.
  TuSimpleConcreteRoad road(3);
  speckle(road.frame.view, 11, 300);
  for (const double X : kDotsX) draw_dot(road.frame.view, road.ground, road.model, X, kLeftLineY - 4820.0, 230);
  PictureLineSearch search(road.c.camera);
  const PictureLine& l = look_right(search, road);
  EXPECT_GT(l.hits, PictureLineSearch::kMinHits);  // they are seen, at the end
  EXPECT_NEAR(l.offset_mm, -4800.0, PictureLineSearch::kOffsetStepMm);
  EXPECT_FALSE(l.found);
}

TEST(PictureLineSearch, ATrackedWindowTakesALineWhoseOwnHitsFillIt) {
  // A dashed line of paint (3 m dashes, 9 m gaps) where the markers were, with a rough
  // strip of concrete beside it (a patch, worn paint: specks 200-700 mm right of the
  // line), looked for as a tracked frame looks for it: taken only within
  // kTrackedWindowMm (600 mm) of where the previous frame had it. The line's bars and
  // the strip's specks are most of the window's candidates' hits: chance measured there
  // alone is the line's surroundings, and the road looks textured (TuSimple still 37,
  // held: its right line of dashes lost on every tracked frame). Measured across every
  // lane width, chance is the road's.
  TuSimpleConcreteRoad road(3);
  speckle(road.frame.view, 11, 300);
  for (double X = 4000.0; X < 40000.0; X += 12000.0)
    draw_band(road.frame.view, road.ground, road.model, kDotsY, X, X + 3000.0, 130.0, 230);
  std::uint32_t seed = 17;
  for (int i = 0; i < 400; ++i) {  // the strip's specks, 3-40 m ahead
    seed = seed * 1664525u + 1013904223u;
    const double X = 3000.0 + (seed >> 8) % 37000u;
    seed = seed * 1664525u + 1013904223u;
    const double Y = kDotsY - 200.0 - (seed >> 8) % 500u;
    if (const auto px = road.model.pixel_from_point(Vec3(X, Y, 0.0)))
      if (px->x() >= 1.0 && px->x() < road.frame.view.width - 1 && px->y() >= 1.0 && px->y() < road.frame.view.height)
        road.frame.view.row(static_cast<int>(px->y()) - 1)[static_cast<int>(px->x()) - 1] = 190;
  }
  const double last = kDotsY - kLeftLineY, window = 600.0;
  PictureLineSearch search(road.c.camera);
  const PictureLine& narrow = search.find(road.frame.view, road.pose, kLeftLine, last - window, last + window, 3000.0,
                                          40000.0, 130.0, kMinContrast);
  EXPECT_GT(narrow.baseline, PictureLineSearch::kMaxChanceHits) << "chance measured within the window";
  EXPECT_FALSE(narrow.found);
  const PictureLine& l =
      search.find(road.frame.view, road.pose, kLeftLine, -4800.0, -2600.0, 3000.0, 40000.0, 130.0, kMinContrast,
                  ChanceRule::clean_road, PictureLineSearch::Window{last - window, last + window});
  ASSERT_TRUE(l.found) << l.hits << " hits, chance " << l.baseline << " +- " << l.spread;
  EXPECT_LE(l.baseline, PictureLineSearch::kMaxChanceHits);
  EXPECT_NEAR(l.offset_mm, last, PictureLineSearch::kOffsetStepMm);
}

TEST(PictureLineSearch, ATrackedWindowTakesNoLineOutsideIt) {
  // The markers a lane's width away, the window 900 mm off them: chance across every
  // width, but the line, outside the window, is not taken (nor its edge's hits).
  TuSimpleConcreteRoad road(3);
  speckle(road.frame.view, 11, 300);
  for (const double X : kDotsX) draw_dot(road.frame.view, road.ground, road.model, X, kDotsY, 230);
  const double last = kDotsY - kLeftLineY + 900.0;
  PictureLineSearch search(road.c.camera);
  EXPECT_FALSE(search
                   .find(road.frame.view, road.pose, kLeftLine, -4800.0, -2600.0, 3000.0, 40000.0, 130.0, kMinContrast,
                         ChanceRule::clean_road, PictureLineSearch::Window{last - 600.0, last + 600.0})
                   .found);
}

// Speckled concrete with the lane's left line of paint and the few markers of its right
// line (kDotsX).
struct LineAndMarkers : TuSimpleConcreteRoad {
  LineAndMarkers() : TuSimpleConcreteRoad(3) {
    speckle(frame.view, 11, 300);
    draw_band(frame.view, ground, model, kLeftLineY, 4000.0, 40000.0, 130.0, 230);
    for (const double X : kDotsX) draw_dot(frame.view, ground, model, X, kDotsY, 230);
  }
};

// The detector with a solid line on the left and the markers on the right, looking again
// from a solve's pose along its line (as a search does, or a tracked frame): the grouping
// finds the line of paint, and the markers, too few for any line it builds from marks,
// are the lane's right line, found in the picture where they are. From a guessed pose (no
// lines to go on) the picture is not searched.
TEST(LaneDetector, AFewMarkersALanesWidthFromTheOnlyLineFoundAreTheLanesOtherLine) {
  const LineAndMarkers road;
  LaneDetector det(road.c.camera, road.c.detection);
  EXPECT_EQ(det.detect(road.frame.view, road.pose, {}).num_lines, 1);
  const RoadLine solved[] = {kLeftLine};
  const DetectionResult& r = det.detect(road.frame.view, road.pose, solved);
  ASSERT_EQ(r.num_lines, 2);
  EXPECT_FALSE(r.lines[0].in_picture);
  EXPECT_NEAR(r.lines[0].fit.y_at(10000.0), kLeftLineY, 50.0);
  const DetectedLine& right = r.lines[1];
  EXPECT_TRUE(right.in_picture);
  EXPECT_TRUE(right.parallel);
  EXPECT_NEAR(right.fit.y_at(10000.0), kDotsY, PictureLineSearch::kOffsetStepMm + 50.0);
  ASSERT_GT(right.num_picks, 0);
  for (const MarkCandidate& m : r.marks)
    if (m.line == 1) {
      EXPECT_NEAR(m.Y, kDotsY, 0.5 * PictureLineSearch::kOffsetStepMm + m.X / 150.0) << m.X;
    }
  // Without the markers there is the left line alone.
  TuSimpleConcreteRoad bare(3);
  speckle(bare.frame.view, 11, 300);
  draw_band(bare.frame.view, bare.ground, bare.model, kLeftLineY, 4000.0, 40000.0, 130.0, 230);
  EXPECT_EQ(det.detect(bare.frame.view, bare.pose, solved).num_lines, 1);
}

// The own lane's right line is the few markers, and the next lane's line beyond them is
// paint the grouping finds: a line on each side, but two lanes apart. A tracked frame
// whose previous frame had the own lane's right line looks for it in the picture where it
// was, as when nothing was found on that side, and takes it no nearer the line beyond
// than a lane's width (TuSimple still 37 held: its right line of dashes held for a step
// beside them, the next lane's found, no lane on any tracked frame). A search's look
// again along its first solve's lines does not.
TEST(LaneDetector, ATrackedFrameLooksForTheOwnLanesLineWhenOnlyTheLineBeyondItIsFound) {
  LineAndMarkers road;
  const double beyond_y = kDotsY - kLaneWidthMm;
  draw_band(road.frame.view, road.ground, road.model, beyond_y, 4000.0, 40000.0, 130.0, 230);
  LaneDetector det(road.c.camera, road.c.detection);
  const RoadLine last_frame[] = {kLeftLine, RoadLine{kDotsY + 80.0, 0.0, 0.0}, RoadLine{beyond_y, 0.0, 0.0}};
  const DetectionResult& r = det.detect(road.frame.view, road.pose, last_frame);
  ASSERT_EQ(r.num_lines, 3);
  EXPECT_NEAR(r.lines[0].fit.y_at(10000.0), kLeftLineY, 50.0);
  EXPECT_TRUE(r.lines[1].in_picture);  // ordered left to right: the new line between the two
  EXPECT_NEAR(r.lines[1].fit.y_at(10000.0), kDotsY, PictureLineSearch::kOffsetStepMm + 50.0);
  EXPECT_FALSE(r.lines[2].in_picture);
  EXPECT_NEAR(r.lines[2].fit.y_at(10000.0), beyond_y, 50.0);
  for (const MarkCandidate& m : r.marks)
    if (m.line == 2) {
      EXPECT_NEAR(m.Y, beyond_y, 200.0) << "the line beyond kept its marks";
    }
  // Without the own line in the previous frame, or on a search's look again, the two
  // lines found are what the frame has.
  const RoadLine without_it[] = {kLeftLine, RoadLine{beyond_y, 0.0, 0.0}};
  EXPECT_EQ(det.detect(road.frame.view, road.pose, without_it).num_lines, 2);
  const RoadLine solved[] = {kLeftLine};
  EXPECT_EQ(det.detect(road.frame.view, road.pose, solved, PictureSearch::own_lane_and_beyond).num_lines, 2);
  // A lane's width apart, the line on each side is the own lane's: nothing is looked for.
  LineAndMarkers lane;
  draw_band(lane.frame.view, lane.ground, lane.model, kDotsY, 4000.0, 40000.0, 130.0, 230);
  const DetectionResult& both = det.detect(lane.frame.view, lane.pose, last_frame);
  ASSERT_EQ(both.num_lines, 2);
  EXPECT_FALSE(both.lines[1].in_picture);
}

// A tracked frame (the previous frame's lines as priors) looks for the other line within
// kTrackedWindowMm (600 mm) of where the previous frame had it: found where the previous
// frame had it a few centimetres off, not where it had it 900 mm off (a different line),
// while a second look (PictureSearch::own_lane_and_beyond) looks across every lane width.
TEST(LaneDetector, ATrackedFrameLooksForTheOtherLineNearWhereThePreviousFrameHadIt) {
  const LineAndMarkers road;
  LaneDetector det(road.c.camera, road.c.detection);
  const RoadLine near_last[] = {kLeftLine, RoadLine{kDotsY + 80.0, 0.0, 0.0}};
  const DetectionResult& near = det.detect(road.frame.view, road.pose, near_last);
  ASSERT_EQ(near.num_lines, 2);
  EXPECT_TRUE(near.lines[1].in_picture);
  EXPECT_NEAR(near.lines[1].fit.y_at(10000.0), kDotsY, PictureLineSearch::kOffsetStepMm + 50.0);
  const RoadLine far_last[] = {kLeftLine, RoadLine{kDotsY + 900.0, 0.0, 0.0}};
  EXPECT_EQ(det.detect(road.frame.view, road.pose, far_last).num_lines, 1);
  const DetectionResult& again = det.detect(road.frame.view, road.pose, far_last, PictureSearch::own_lane_and_beyond);
  ASSERT_EQ(again.num_lines, 2);
  EXPECT_NEAR(again.lines[1].fit.y_at(10000.0), kDotsY, PictureLineSearch::kOffsetStepMm + 50.0);
}

// The next lane's line beyond the own lane's right line, as a few markers a lane's width
// past it: looked for in the picture when detect() is asked to (a still's second look),
// not otherwise (a tracked frame), and not beyond a yellow or a solid line (the travelled
// way's edge: beyond it lie a shoulder and a barrier, and their specks, seams and edges
// are no lane).
constexpr double kRightLineY = kLeftLineY - kLaneWidthMm, kBeyondY = kRightLineY - kLaneWidthMm;
// The lane's two lines as a solve gave them: what detect() looks again along.
const RoadLine kSolvedLane[] = {kLeftLine, RoadLine{kRightLineY, 0.0, 0.0}};
// Seven markers over 11-33 m (nearer, 5.5 m to the side is out of the picture), a few
// of a row's: far away each covers a fraction of a row.
constexpr double kBeyondDotsX[] = {11500.0, 14000.0, 17000.0, 20500.0, 24000.0, 28000.0, 33000.0};

// The lane's two lines of paint, the left one solid, the right one dashed (3 m dashes,
// 9 m gaps) or solid, and the markers beyond its right line; in colour with the right
// line yellow when `yellow_right`.
struct LaneWithMarkersBeyond {
  TuSimpleConcreteRoad road{3};
  test::Frame colour{road.c.camera, PixelFormat::rgb8};
  explicit LaneWithMarkersBeyond(bool yellow_right, bool solid_right = false) {
    speckle(road.frame.view, 11, 300);
    draw_band(road.frame.view, road.ground, road.model, kLeftLineY, 4000.0, 40000.0, 130.0, 230);
    for (const double X : kBeyondDotsX) draw_dot(road.frame.view, road.ground, road.model, X, kBeyondY, 230);
    TuSimpleConcreteRoad right_line{3};  // its pixels: where this frame differs from the bare road
    for (double X = 4000.0; X < 40000.0; X += solid_right ? 36000.0 : 12000.0)
      draw_band(right_line.frame.view, right_line.ground, right_line.model, kRightLineY, X,
                solid_right ? 40000.0 : X + 3000.0, 130.0, 230);
    const TuSimpleConcreteRoad bare{3};
    for (int y = 0; y < road.frame.view.height; ++y)
      for (int x = 0; x < road.frame.view.width; ++x) {
        const bool paint = right_line.frame.view.row(y)[x] != bare.frame.view.row(y)[x];
        if (paint) road.frame.view.row(y)[x] = right_line.frame.view.row(y)[x];
        const std::uint8_t g = road.frame.view.row(y)[x];
        std::uint8_t* rgb = colour.view.row(y) + 3 * x;
        rgb[0] = g, rgb[1] = g, rgb[2] = g;
        if (paint && yellow_right) {
          rgb[1] = static_cast<std::uint8_t>(0.8 * g);
          rgb[2] = static_cast<std::uint8_t>(0.25 * g);
        }
      }
  }
};

TEST(LaneDetector, AFewMarkersALanesWidthBeyondTheOwnLanesLineAreTheNextLanesLine) {
  LaneWithMarkersBeyond scene(false);
  LaneDetector det(scene.road.c.camera, scene.road.c.detection);
  EXPECT_EQ(det.detect(scene.road.frame.view, scene.road.pose, kSolvedLane).num_lines, 2);  // a tracked frame's
  const DetectionResult& r =
      det.detect(scene.road.frame.view, scene.road.pose, kSolvedLane, PictureSearch::own_lane_and_beyond);
  ASSERT_EQ(r.num_lines, 3);
  EXPECT_FALSE(r.lines[0].in_picture);
  EXPECT_FALSE(r.lines[1].in_picture);
  EXPECT_NEAR(r.lines[1].fit.y_at(10000.0), kRightLineY, 50.0);
  const DetectedLine& beyond = r.lines[2];  // ordered left to right
  EXPECT_TRUE(beyond.in_picture);
  EXPECT_NEAR(beyond.fit.y_at(10000.0), kBeyondY, PictureLineSearch::kOffsetStepMm + 50.0);
  ASSERT_GT(beyond.num_picks, 0);
  for (const MarkCandidate& m : r.marks) {
    if (m.line == 2) {
      EXPECT_NEAR(m.Y, kBeyondY, 0.5 * PictureLineSearch::kOffsetStepMm + m.X / 150.0) << m.X;
    }
    if (m.line == 1) {
      EXPECT_NEAR(m.Y, kRightLineY, 200.0) << m.X;  // the right line's marks kept their line
    }
  }
}

TEST(LaneDetector, NoLaneIsLookedForBeyondASolidLine) {
  LaneWithMarkersBeyond solid(false, true);
  LaneDetector det(solid.road.c.camera, solid.road.c.detection);
  const DetectionResult& r =
      det.detect(solid.road.frame.view, solid.road.pose, kSolvedLane, PictureSearch::own_lane_and_beyond);
  ASSERT_EQ(r.num_lines, 2);
  EXPECT_NEAR(r.lines[1].fit.y_at(10000.0), kRightLineY, 50.0);
}

TEST(LaneDetector, NoLaneIsLookedForBeyondAYellowLine) {
  LaneWithMarkersBeyond grey(false), yellow(true);
  LaneDetector det(grey.road.c.camera, grey.road.c.detection);
  // In colour with the right line white the markers are found beyond it, as in grey.
  const DetectionResult& white =
      det.detect(grey.colour.view, grey.road.pose, kSolvedLane, PictureSearch::own_lane_and_beyond);
  ASSERT_EQ(white.num_lines, 3);
  EXPECT_FALSE(white.lines[1].yellow);
  const DetectionResult& r =
      det.detect(yellow.colour.view, yellow.road.pose, kSolvedLane, PictureSearch::own_lane_and_beyond);
  ASSERT_EQ(r.num_lines, 2);
  EXPECT_TRUE(r.lines[1].yellow);
}

}  // namespace
}  // namespace ccdlane
