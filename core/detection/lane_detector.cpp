// Lane detector: row plan from the pose, row filter, road-plane and orientation checks,
// grouping, picks.
#include "core/detection/lane_detector.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/detection/contrast_threshold.hpp"
#include "core/detection/paint_measure.hpp"
#include "core/geometry/types.hpp"

namespace ccdlane {
namespace {

static_assert(kMaxDetectedLines == kMaxLaneLines, "detection reports at most what the solver takes");

constexpr int kMaxScanRows = 360;              // beyond, rows are subsampled evenly
constexpr int kCandidatesPerPixelRow = 24;     // capacity: marks per scanned row, on average
constexpr double kMinMarkPx = 0.8;             // marks narrower than this are not resolved
constexpr double kOrientationTolerance = 0.5;  // sin(30 deg): between a bar and the way to the vanishing point
// The lane widths a line is looked for at in the picture, beside the own lane's line it
// is the other line of, or beyond (lane_metrics.hpp's bounds, less the widest: a lane
// that wide is two lanes whose line between was missed).
constexpr double kMinOwnLaneWidthMm = 2600.0;
constexpr double kMaxOwnLaneWidthMm = 4800.0;
// A tracked frame takes the own lane's other line only this far either side of where the
// previous frame had it: a lane's width changes by centimetres from one frame to the next.
// Chance's hits are still measured across every lane width (PictureLineSearch::Window):
// within 600 mm of a dashed line of paint, its own bars are most candidates' hits.
constexpr double kTrackedWindowMm = 600.0;
// A line with marks on this share of the scan rows it spans is solid: dashes (3 m of 12,
// Europe's 6 of 18) cover a quarter to a third of them; a solid line loses some to
// occlusion, wear and shadow.
constexpr double kSolidLineCoverage = 0.6;
// How far to the side rows are scanned, on the road: detection reports the lines nearest
// the vehicle (at most 4, within 2.5 lane widths, 9 m), and grouping gates them a metre
// wide; beyond that, with room for a yaw error of 3 degrees (0.05 per mm ahead), paint
// is never reported and is not looked at.
constexpr double kLateralReachMm = 12000.0;
constexpr double kLateralReachPerMm = 0.05;
// A Botts' dot or raised marker is about 10 cm long on the road; blur and a pose error
// make it look longer. Anything that stands above its surroundings over less of the road
// than this (plus a pixel or two of blur) is a blob, not a piece of a line.
constexpr double kMaxDotLengthMm = 300.0;
constexpr double kMaxDotWidthMm = 250.0;
// A marker is a dome: in sunlight only its lit side stands out, about half of its
// 10 cm, the other half is its shadow. Bars that narrow are kept as possible dots.
constexpr double kMinDotLitWidthMm = 40.0;
constexpr double kDotBlurPx = 2.0;
// Lit from one side, a marker is a cap beside its shadow (dot_scanner.hpp), looked for
// where the dome (10 cm) spans this many pixels: fewer, and cap and shadow blur into one.
constexpr double kDotDiameterMm = 100.0;
constexpr double kMinShadowedDotPx = 2.5;
// A zebra crossing's bars run along the road as lane lines do, a dash long, 0.3-0.6 m
// wide and as far apart (continental crossings: 0.5 m bars 0.5 m apart in Europe, 12-24
// in. bars 1-5 ft apart in the US), across every lane. Lane lines lie a lane's width
// apart on a row, and are narrower: 10-20 cm, and a double line's two stripes, a
// buffer's two double lines (California's HOV lanes: four stripes within 2 m) or a line
// and a marker beside it lie closer. This many bars at least kMinCrossingBarMm wide in a
// row across the road, each within kMaxCrossingGapMm of the next, are none of them a
// line's: beside a line, a bar of the crossing is a dash to grouping.
constexpr int kMinCrossingBars = 4;
constexpr double kMinCrossingBarMm = 250.0;
constexpr double kMaxCrossingGapMm = 1500.0;
// A crossing's bars are one paint in one light: the weakest at least this share of the
// strongest's contrast. Concrete's seams and texture beside a line are bars too, of a
// tenth to a third of paint's contrast (segB), and no crossing with it. Bars with a step
// beside them (held for a line beyond, lane_marks.hpp) are kerbs, seams and slab edges:
// not a crossing's either.
constexpr double kCrossingContrastRatio = 0.5;
constexpr double kRowsPerMarkerForEveryFourth = 4.0;
// Contrast markings' black borders are 75-100 mm wide (3-4 in., some US states on pale
// concrete); a band this wide at least beside each of a bar's edges is one.
constexpr double kMinContrastBorderMm = 50.0;
// Joints between concrete slabs are sealed cuts a centimetre or two wide; with blur and
// a worn edge, this wide at most.
constexpr double kMaxJointWidthMm = 40.0;
// A joint's piece on the next scan row lies within this (plus half their widths) of where
// the line from the vanishing point through it crosses that row.
constexpr double kJointLinkPx = 1.5;
// A line's dots needed to say how far beside its joint they lie: each is placed to a
// pixel or so (10-35 mm at 10-35 m), a few of them to a centimetre.
constexpr int kMinDotsBesideJoint = 3;
// A double line is two stripes of paint side by side (a no-passing line, a carpool
// lane's edge): 10-15 cm each with 10-30 cm between them, their middles this far apart,
// with room for an unsettled height's scale. Its second stripe is paint as the first is:
// as wide, give or take this factor, and as bright, give or take twice; and it runs
// beside it along most of it, at one distance (within this share of it, or the spread).
constexpr double kMinStripeGapMm = 150.0;
constexpr double kMaxStripeGapMm = 600.0;
constexpr double kStripeWidthRatio = 1.6;
constexpr double kStripeContrastRatio = 2.0;
constexpr double kStripeGapShare = 0.2;
constexpr double kStripeGapSpreadMm = 60.0;
constexpr int kMinStripePairs = 8;
// Yellow paint stands above the road mostly by its colour (on pale concrete, by its
// colour alone): its yellowness is at least this fraction of its contrast, and above
// the tint of grey surfaces (a few levels) by this much. White paint's is near 0.
constexpr double kYellowShareOfContrast = 0.5;
constexpr int kMinYellowness = 20;

// The widest a joint between slabs (or a sealed crack's bead) looks where one pixel spans
// `mm_per_px` of the road across it.
double max_joint_px(double mm_per_px) { return kMaxJointWidthMm / mm_per_px + kDotBlurPx; }

// 3x3 Sobel gradient of the paint measure at a 0-based pixel (1 <= x <= W-2, 1 <= y <= H-2).
void sobel(const ImageView& im, int x, int y, double& gx, double& gy) {
  int p[3][3];  // each neighbour's measure read once, [row][column]
  for (int dy = 0; dy < 3; ++dy)
    for (int dx = 0; dx < 3; ++dx) p[dy][dx] = paint_measure_at(im, x + dx - 1, y + dy - 1);
  gx = (p[0][2] + 2 * p[1][2] + p[2][2]) - (p[0][0] + 2 * p[1][0] + p[2][0]);
  gy = (p[2][0] + 2 * p[2][1] + p[2][2]) - (p[0][0] + 2 * p[0][1] + p[0][2]);
}

// The rows column x of `image` stays `so` over from row y on, going `step` (y itself not
// counted); -1 when that reaches beyond `limit` rows or the picture.
template <typename Test>
int rows_so(const ImageView& image, int x, int y, int step, int limit, const Test& so) {
  int n = 0;
  for (int yy = y + step; n <= limit; yy += step, ++n) {
    if (yy < 0 || yy >= image.height) return -1;
    if (!so(x, yy)) return n;
  }
  return -1;
}

// How many rows a marker may span where one row spans `mm_per_px_down` of the road (at
// least 1 mm); 0 where a row spans more of the road than a marker is long: farther, a
// dash is a few rows tall too, and blobs are not told from paint.
int dot_rows_for(double mm_per_px_down) {
  if (mm_per_px_down > kMaxDotLengthMm) return 0;
  return static_cast<int>(std::ceil(kMaxDotLengthMm / mm_per_px_down + kDotBlurPx));
}

// How many pixels of row yy, columns xa to xb, are `so`.
template <typename Test>
int count_so(int xa, int xb, int yy, const Test& so) {
  int n = 0;
  for (int x = xa; x <= xb; ++x) n += so(x, yy);
  return n;
}

}  // namespace

LaneDetector::LaneDetector(const CameraSpec& camera, const DetectionConfig& config)
    : camera_(camera),
      config_(config),
      scanner_(camera.Nu),
      grouper_(static_cast<int>(std::min(camera.Nv, kMaxScanRows)) * kCandidatesPerPixelRow),
      picture_line_(camera),
      rows_(static_cast<std::size_t>(camera.Nv)),
      row_share_(static_cast<std::size_t>(camera.Nv)),
      row_contrast_(static_cast<std::size_t>(camera.Nv)),
      marks_(static_cast<std::size_t>(std::min(camera.Nv, kMaxScanRows)) * kCandidatesPerPixelRow),
      joints_(marks_.size()),
      linked_(marks_.size()),
      row_bars_(marks_.size()),
      crossing_(marks_.size()),
      picks_(static_cast<std::size_t>(config.max_picks)) {}

void LaneDetector::plan_rows(const CameraPose& pose, double curvature_per_mm, bool joints) {
  projector_.set(camera_, pose);
  const CameraModel model(camera_, pose);
  num_rows_ = 0;
  const double col = camera_.cx;
  const int first = std::max(1, config_.roi_top_px), end = camera_.Nv - 1 - config_.hood_px;
  for (int y = first; y < end; ++y) {
    double X = 0, Y = 0, X2 = 0, Y2 = 0;
    if (!projector_.ground(col, y + 1.0, X, Y) || X < config_.min_range_mm || X > config_.max_range_mm) continue;
    if (!projector_.ground(col + 1.0, y + 1.0, X2, Y2)) continue;
    const double mm_per_px = Vec2(X2 - X, Y2 - Y).norm();
    const double mark_px = config_.mark_width_mm / mm_per_px;
    const double min_px = config_.min_mark_width_mm / mm_per_px, max_px = config_.max_mark_width_mm / mm_per_px;
    if (mark_px < kMinMarkPx) continue;
    // Near rows are dense on the road and their marks wide: every second or third one
    // says as much as all of them, at a fraction of the time; every fourth where a raised
    // marker spans four rows or more (each is still crossed by one).
    double X_below = 0.0, Y_below = 0.0;
    const bool below = projector_.ground(col, y + 2.0, X_below, Y_below);
    const bool marker_rows = below && X > X_below && kDotDiameterMm >= kRowsPerMarkerForEveryFourth * (X - X_below);
    const int thin = mark_px >= 12.0 ? (marker_rows ? 4 : 3) : mark_px >= 6.0 ? 2 : 1;
    if (y % thin != 0) continue;
    ScanRow& r = rows_[static_cast<std::size_t>(num_rows_++)];
    r.y = y;
    r.mark_px = static_cast<float>(mark_px);
    r.half_width = std::clamp(static_cast<int>(std::lround(mark_px / 2)), 1, 8);
    // Paint of the accepted widths, with room for blur and a dash's end (narrower) and for
    // the widening towards the picture's edges and one pixel of blur (wider); beyond
    // that, bars are not paint on the road: a barrier's foot seen from a few metres, a
    // kerb's top, text, arrows, patches, cars.
    r.min_width_px = static_cast<float>(std::max(0.8, 0.5 * min_px - 1.0));
    r.max_width_px = static_cast<float>(1.15 * max_px + 2.0);
    r.min_dot_width_px = static_cast<float>(std::max(1.0, kMinDotLitWidthMm / mm_per_px - 1.0));
    // Markers lit from one side, where they are told from paint at all (is_dot: a row
    // spanning more of the road than a marker is long makes a dash a few rows tall too).
    const double dot_px = kDotDiameterMm / mm_per_px;
    const bool dots_told = below && dot_rows_for(std::max(1.0, X - X_below)) > 0;
    r.dot_px = dots_told && dot_px >= kMinShadowedDotPx ? static_cast<float>(dot_px) : 0.0f;
    // Joints, where markers are looked for: a joint only ever joins a row of them.
    r.max_joint_px = joints && r.dot_px > 0.0f ? static_cast<float>(max_joint_px(mm_per_px)) : 0.0f;
    r.min_border_px = static_cast<float>(std::max(1.0, kMinContrastBorderMm / mm_per_px - 1.0));
    // The columns of the road within reach on this row (its centre's distance), where the
    // road bends as the previous frame's lines did. Outside the picture's side edges the
    // projection may not exist: then the row's end.
    const double reach = kLateralReachMm + kLateralReachPerMm * X, bend = curvature_per_mm * X * X;
    const auto left = model.pixel_from_point(Vec3(X, bend + reach, 0.0));
    const auto right = model.pixel_from_point(Vec3(X, bend - reach, 0.0));
    const int margin = 2 * (r.half_width + static_cast<int>(std::ceil(r.max_width_px)));  // the bar's flanks
    r.x_begin = left && left->x() > 0.0 ? std::max(0, static_cast<int>(left->x()) - margin) : 0;
    r.x_end =
        right && right->x() < camera_.Nu ? std::min(camera_.Nu, static_cast<int>(right->x()) + margin) : camera_.Nu;
  }
  if (num_rows_ > kMaxScanRows) {  // keep an even spread
    const int n = num_rows_;
    for (int k = 0; k < kMaxScanRows; ++k)
      rows_[static_cast<std::size_t>(k)] = rows_[static_cast<std::size_t>(static_cast<long>(k) * n / kMaxScanRows)];
    num_rows_ = kMaxScanRows;
  }
}

bool LaneDetector::points_to_vanishing_point(const ImageView& image, const MarkCandidate& c) const {
  if (!have_vp_) return true;
  const int y = static_cast<int>(c.py) - 1;
  const int xa = static_cast<int>(std::lround(c.left_px - 1.0)), xb = static_cast<int>(std::lround(c.right_px - 1.0));
  if (y < 1 || y + 2 > image.height || xa < 1 || xb + 2 > image.width) return false;
  double gax, gay, gbx, gby;
  sobel(image, xa, y, gax, gay);
  sobel(image, xb, y, gbx, gby);
  const double gx = gax - gbx, gy = gay - gby;  // both edges' normals, same sense
  // The bar's way to the vanishing point, in ideal pixels.
  const double dx = c.px() - camera_.cx, dy = c.py - camera_.cy;
  const double s = 1.0 / (1.0 + camera_.k_px2 * (dx * dx + dy * dy));
  // On a bend the road runs towards another point at each distance: its tangent's, the
  // slope m + 2 c X of y = y0 + m x + c x^2 there (a mark 12 m ahead on a 80 m bend runs
  // 8.6 degrees off the straight road, and near the horizon that turns its way in the
  // picture by tens of degrees).
  double vx = vp_x_, vy = vp_y_;
  if (road_c_per_mm_ != 0.0 && !projector_.vanishing_point(road_m_ + 2.0 * road_c_per_mm_ * c.X, vx, vy)) return true;
  const double ex = vx - (camera_.cx + dx * s), ey = vy - (camera_.cy + dy * s);
  const double en = Vec2(ex, ey).norm(), gn = Vec2(gx, gy).norm();
  if (en < 1.0 || gn == 0.0) return true;
  return std::abs(gx * ex + gy * ey) / (gn * en) < kOrientationTolerance;
}

int LaneDetector::dot_rows_limit(double px, double py, double X) const {
  double X_below = 0.0, Y_below = 0.0;
  if (!projector_.ground(px, py + 1.0, X_below, Y_below)) return 0;
  return dot_rows_for(std::max(1.0, X - X_below));
}

double LaneDetector::mm_per_px_across(const MarkCandidate& c) const {
  double X_right = 0.0, Y_right = 0.0;
  if (!projector_.ground(c.px() + 1.0, c.py, X_right, Y_right)) return 0.0;
  return Vec2(X_right - c.X, Y_right - c.Y).norm();
}

bool LaneDetector::is_dot(const ImageView& image, MarkCandidate& c, float levels_per_grey) const {
  // How many rows the bar's centre column stays bright above and below the scanned row.
  // A line (or a dash, 3 m long) stays bright over many rows; a dot only over its own few.
  const int limit = dot_rows_limit(c.px(), c.py, c.X);
  const double across = limit > 0 ? mm_per_px_across(c) : 0.0;
  if (!(across > 0.0) || c.width_px() * across > kMaxDotWidthMm) return false;
  const int x = static_cast<int>(std::lround(c.px() - 1.0)), y = static_cast<int>(c.py) - 1;
  const int xa = static_cast<int>(std::floor(c.left_px - 1.0)), xb = static_cast<int>(std::ceil(c.right_px - 1.0));
  if (xa < 0 || xb >= image.width) return false;
  const float centre = static_cast<float>(paint_measure_at(image, x, y));
  const float threshold = centre - 0.5f * static_cast<float>(c.contrast) * levels_per_grey;
  const auto bright = [&](int px, int py) { return static_cast<float>(paint_measure_at(image, px, py)) >= threshold; };
  const int up = rows_so(image, x, y, -1, limit, bright), down = rows_so(image, x, y, +1, limit, bright);
  if (up < 0 || down < 0 || up + down + 1 > limit) return false;
  // Beyond its ends a blob is dark but for a little of its tilt or blur; a bar crossing
  // the row at a slant (a shadow's edge, a car's trim) goes on, as bright and as wide,
  // beside the centre column.
  const int w = xb - xa + 1;
  for (const int yy : {y - up - 1, y + down + 1})
    if (2 * count_so(std::max(0, xa - w), std::min(image.width - 1, xb + w), yy, bright) > w) return false;
  c.dot_top = static_cast<std::int16_t>(y + 1 - up);
  c.dot_bottom = static_cast<std::int16_t>(y + 1 + down);
  return true;
}

bool LaneDetector::is_shadowed_dot(const ImageView& image, MarkCandidate& c, float levels_per_grey) const {
  // As is_dot, for the cap and the shadow each: the cap's centre column stays bright,
  // the shadow's dark, over no more rows than a marker is long, and beyond the cap's
  // ends the road is not lit as wide as the cap (a bright edge along a dark one, both
  // long: the side of a seam, a car's trim over its shadow).
  const int limit = dot_rows_limit(c.px(), c.py, c.X);
  if (limit == 0) return false;
  const double edge = c.px() - 1.0, cap_w = 0.5 * c.width_px();  // 0-based
  const int y = static_cast<int>(c.py) - 1;
  const int x_cap = static_cast<int>(std::lround(edge - 0.5 * c.shadow_side * cap_w));
  const int x_shadow = static_cast<int>(std::lround(edge + 0.5 * c.shadow_side * static_cast<double>(c.shadow_px)));
  const int xa = static_cast<int>(std::floor(std::min(edge, edge - c.shadow_side * cap_w)));
  const int xb = static_cast<int>(std::ceil(std::max(edge, edge - c.shadow_side * cap_w)));
  const int w = xb - xa + 1;
  if (std::min({x_cap, x_shadow, xa - w}) < 0 || std::max({x_cap, x_shadow, xb + w}) >= image.width) return false;
  const float half = 0.5f * static_cast<float>(c.contrast) * levels_per_grey;
  const float lit = static_cast<float>(paint_measure_at(image, x_cap, y)) - half;
  const float dark = static_cast<float>(paint_measure_at(image, x_shadow, y)) + half;
  const auto bright = [&](int px, int py) { return static_cast<float>(paint_measure_at(image, px, py)) >= lit; };
  const auto shaded = [&](int px, int py) { return static_cast<float>(paint_measure_at(image, px, py)) <= dark; };
  const int up = rows_so(image, x_cap, y, -1, limit, bright), down = rows_so(image, x_cap, y, +1, limit, bright);
  const int shadow_up = rows_so(image, x_shadow, y, -1, limit, shaded);
  const int shadow_down = rows_so(image, x_shadow, y, +1, limit, shaded);
  if (std::min({up, down, shadow_up, shadow_down}) < 0 || up + down + 1 > limit || shadow_up + shadow_down + 1 > limit)
    return false;
  // A lit dome's cap is a crescent: beyond its centre column's ends its tips go on
  // beside it for a row, narrower than it; a bar does so as wide.
  for (const int yy : {y - up - 1, y + down + 1})
    if (count_so(xa - w, xb + w, yy, bright) >= w) return false;
  c.dot_top = static_cast<std::int16_t>(y + 1 - up);
  c.dot_bottom = static_cast<std::int16_t>(y + 1 + down);
  return true;
}

int LaneDetector::keep_one_sun(int kept) {
  // One sun lights every marker of a picture from the same side: markers found as a cap
  // beside a shadow falling the other way than most are something else (a speck on a
  // shadow's border, a car's trim, noise), and are dropped.
  int right = 0, left = 0;
  for (int i = 0; i < kept; ++i) {
    right += marks_[static_cast<std::size_t>(i)].shadow_side > 0;
    left += marks_[static_cast<std::size_t>(i)].shadow_side < 0;
  }
  if (right == 0 && left == 0) return kept;
  const std::int8_t shadow_side = right >= left ? 1 : -1;
  int n = 0;
  for (int i = 0; i < kept; ++i) {
    MarkCandidate c = marks_[static_cast<std::size_t>(i)];
    if (c.shadow_side == -shadow_side) continue;
    // A marker the row filter's bar pass found by its lit cap alone: in this sunlight the
    // cap is the dome's sunny half, whose middle lies a quarter of a marker from the
    // dome's, away from the shadow (blur widens the cap, not that).
    const double across = c.dot && c.shadow_side == 0 ? mm_per_px_across(c) : 0.0;
    if (across > 0.0) {
      const double shift = shadow_side * 0.25 * kDotDiameterMm / across;
      c.left_px += shift;
      c.right_px += shift;
      if (!on_the_road(c)) continue;
    }
    marks_[static_cast<std::size_t>(n++)] = c;
  }
  result_.counters.dots -= kept - n;
  result_.counters.against_the_sun = kept - n;
  return n;
}

int LaneDetector::drop_crossings(int kept) {
  // Candidates come in scan-row order; a row's bars of a crossing's width (not markers,
  // not joints: neither is a crossing's) sorted by where they lie across the road.
  int n = 0;
  for (int begin = 0; begin < kept;) {
    const std::int16_t row = marks_[static_cast<std::size_t>(begin)].scan_row;
    // Across one row the road's millimetres per pixel are one (a flat road, level).
    const double mm_per_px = row_mm_per_px(rows_[static_cast<std::size_t>(row)]);
    int end = begin, bars = 0;
    for (; end < kept && marks_[static_cast<std::size_t>(end)].scan_row == row; ++end) {
      const MarkCandidate& c = marks_[static_cast<std::size_t>(end)];
      if (c.dot || c.joint || c.for_lines_beyond) continue;
      if ((c.right_px - c.left_px) * mm_per_px >= kMinCrossingBarMm) row_bars_[static_cast<std::size_t>(bars++)] = end;
    }
    const auto bar = [this](int k) -> const MarkCandidate& {
      return marks_[static_cast<std::size_t>(row_bars_[static_cast<std::size_t>(k)])];
    };
    const auto across = [this](int a, int b) {
      return marks_[static_cast<std::size_t>(a)].Y < marks_[static_cast<std::size_t>(b)].Y;
    };
    std::sort(row_bars_.begin(), row_bars_.begin() + bars, across);
    // Runs of bars each within kMaxCrossingGapMm of the next, of one paint's contrast.
    for (int a = 0; a < bars;) {
      int b = a + 1;
      double weakest = bar(a).contrast, strongest = weakest;
      for (; b < bars && bar(b).Y - bar(b - 1).Y <= kMaxCrossingGapMm; ++b) {
        weakest = std::min(weakest, bar(b).contrast);
        strongest = std::max(strongest, bar(b).contrast);
      }
      if (b - a >= kMinCrossingBars && weakest >= kCrossingContrastRatio * strongest)
        for (int k = a; k < b; ++k) crossing_[static_cast<std::size_t>(row_bars_[static_cast<std::size_t>(k)])] = 1;
      a = b;
    }
    for (int i = begin; i < end; ++i) {
      if (crossing_[static_cast<std::size_t>(i)]) {
        crossing_[static_cast<std::size_t>(i)] = 0;
        ++result_.counters.crossing_bars;
        continue;
      }
      marks_[static_cast<std::size_t>(n++)] = marks_[static_cast<std::size_t>(i)];
    }
    begin = end;
  }
  return n;
}

int LaneDetector::keep_linked_joints(int kept) {
  // Candidates come in scan-row order. A piece of a joint on one row has another on the
  // next row where the line from the vanishing point through it crosses that row; cracks
  // run every way, and specks and texture are a row long. Cheaper than the bars' edge
  // test (keep_linked_joints sees a few hundred pieces a frame), and sharper for lines a
  // pixel or two wide, whose edges' gradients are mostly noise.
  int n = 0;
  for (int i = 0; i < kept; ++i)
    if (marks_[static_cast<std::size_t>(i)].joint) {
      joints_[static_cast<std::size_t>(n)] = i;
      linked_[static_cast<std::size_t>(n++)] = !have_vp_;
    }
  for (int a = 0; a < n && have_vp_; ++a) {
    const MarkCandidate& p = marks_[static_cast<std::size_t>(joints_[static_cast<std::size_t>(a)])];
    for (int b = a + 1; b < n; ++b) {
      const MarkCandidate& q = marks_[static_cast<std::size_t>(joints_[static_cast<std::size_t>(b)])];
      if (q.scan_row == p.scan_row) continue;
      if (q.scan_row > p.scan_row + 1) break;
      const double x = vp_x_ + (p.px() - vp_x_) * (q.py - vp_y_) / (p.py - vp_y_);
      if (std::abs(q.px() - x) <= kJointLinkPx + 0.5 * (p.width_px() + q.width_px()))
        linked_[static_cast<std::size_t>(a)] = linked_[static_cast<std::size_t>(b)] = 1;
    }
  }
  int out = 0, j = 0;
  for (int i = 0; i < kept; ++i) {
    const MarkCandidate& c = marks_[static_cast<std::size_t>(i)];
    if (c.joint && !linked_[static_cast<std::size_t>(j++)]) {
      ++result_.counters.wrong_orientation;
      continue;
    }
    result_.counters.joints += c.joint;
    marks_[static_cast<std::size_t>(out++)] = c;
  }
  return out;
}

double LaneDetector::row_mm_per_px(const ScanRow& r) const {
  return config_.mark_width_mm / static_cast<double>(r.mark_px);
}

bool LaneDetector::between_beads(const ImageView& image, const MarkCandidate& c) const {
  const ScanRow& r = rows_[static_cast<std::size_t>(c.scan_row)];
  const int bead = static_cast<int>(std::ceil(max_joint_px(row_mm_per_px(r))));
  constexpr int flank = 3;  // pixels of road read beyond the valley
  const int y = static_cast<int>(c.py) - 1;
  const int a = static_cast<int>(std::lround(c.left_px - 1.0)), b = static_cast<int>(std::lround(c.right_px - 1.0));
  if (a - bead - flank < 0 || b + bead + flank >= image.width || b < a) return false;
  // The road's level beyond a valley within `bead` of the edge, when the valley is that
  // much darker than it (most bars have none: the bar's own level is read only then).
  const auto road_beyond_valley = [&](int edge, int step) -> std::optional<float> {
    int beyond = 0;
    for (int k = 0; k < flank; ++k) beyond += paint_measure_at(image, edge + step * (bead + k), y);
    const float road = static_cast<float>(beyond) / static_cast<float>(flank);
    for (int k = 0; k < bead; ++k)
      if (static_cast<float>(paint_measure_at(image, edge + step * k, y)) <= road - min_contrast_) return road;
    return std::nullopt;
  };
  const std::optional<float> left = road_beyond_valley(a - 1, -1);
  if (!left) return false;
  const std::optional<float> right = road_beyond_valley(b + 1, +1);
  if (!right) return false;
  // The bar's middle half: its edges, placed by a box derivative wider than a far bar,
  // may take in the dark beside it (contrast markings' black borders).
  const int quarter = (b - a) / 4;
  int inside = 0;
  for (int x = a + quarter; x <= b - quarter; ++x) inside += paint_measure_at(image, x, y);
  // As bright as the road beyond, to the minimum contrast: paint and a raised marker (a
  // dome between its shadow and a joint) stand above it. (Over the whole bar, its edges
  // darkened by the beads, half the minimum contrast was the margin.)
  const float level = static_cast<float>(inside) / static_cast<float>(b - a - 2 * quarter + 1) - min_contrast_;
  return *left >= level && *right >= level;
}

bool LaneDetector::is_yellow(const ImageView& image, const MarkCandidate& c) {
  // The bar's centre and its two neighbours along the row: one pixel may be a JPEG or
  // chroma-subsampling artefact.
  const int x = static_cast<int>(std::lround(c.px() - 1.0)), y = static_cast<int>(c.py) - 1;
  if (x < 1 || x + 1 >= image.width || y < 0 || y >= image.height) return false;
  const int yellowness =
      paint_yellowness_at(image, x - 1, y) + paint_yellowness_at(image, x, y) + paint_yellowness_at(image, x + 1, y);
  return yellowness >= 3 * kMinYellowness && yellowness >= 3.0 * kYellowShareOfContrast * c.contrast;
}

double LaneDetector::dots_beside_joint_mm(int j) const {
  const RoadLine& fit = result_.lines[static_cast<std::size_t>(j)].fit;
  double dots = 0.0, joint = 0.0;
  int num_dots = 0, num_joint = 0;
  for (const MarkCandidate& m : result_.marks) {
    if (m.line != j) continue;
    const double across = m.Y - fit.y_at(m.X);
    if (m.joint) {
      joint += across;
      ++num_joint;
    } else if (m.dot) {
      dots += across;
      ++num_dots;
    }
  }
  if (num_dots < kMinDotsBesideJoint || num_joint == 0) return 0.0;
  return dots / num_dots - joint / num_joint;
}

double LaneDetector::double_line_middle_mm(int j) const {
  // Rows where the line has a bar of paint and another bar of paint that joined no line
  // lies beside it, as wide and as bright, a double line's gap away. Marks come in scan
  // row order: a row's bars are neighbours.
  const std::span<const MarkCandidate> marks = result_.marks;
  const auto paint = [](const MarkCandidate& m) { return !m.dot && !m.joint && !m.for_lines_beyond; };
  const auto stripes = [&](const MarkCandidate& own, const MarkCandidate& other) {  // on one scan row
    const double gap = other.Y - own.Y;
    return other.line < 0 && paint(other) && std::abs(gap) >= kMinStripeGapMm && std::abs(gap) <= kMaxStripeGapMm &&
           other.width_px() <= kStripeWidthRatio * own.width_px() &&
           own.width_px() <= kStripeWidthRatio * other.width_px() &&
           other.contrast <= kStripeContrastRatio * own.contrast &&
           own.contrast <= kStripeContrastRatio * other.contrast;
  };
  // Every such pair's gap, to each side; then, on the side with more, those at one gap
  // about their mean (a second stripe is at one distance, clutter at any).
  int own_bars = 0;
  const auto for_each_pair = [&](const auto& take) {
    for (std::size_t i = 0; i < marks.size(); ++i) {
      const MarkCandidate& own = marks[i];
      if (own.line != j || !paint(own)) continue;
      for (std::size_t k = i; k-- > 0 && marks[k].scan_row == own.scan_row;)
        if (stripes(own, marks[k])) take(marks[k].Y - own.Y);
      for (std::size_t k = i + 1; k < marks.size() && marks[k].scan_row == own.scan_row; ++k)
        if (stripes(own, marks[k])) take(marks[k].Y - own.Y);
    }
  };
  for (const MarkCandidate& m : marks) own_bars += m.line == j && paint(m);
  double sum[2] = {0.0, 0.0};
  int count[2] = {0, 0};
  for_each_pair([&](double gap) {
    sum[gap > 0.0] += gap;
    ++count[gap > 0.0];
  });
  const int side = count[1] > count[0] ? 1 : 0;
  if (count[side] < kMinStripePairs) return 0.0;
  const double mean = sum[side] / count[side];
  const double spread = std::max(kStripeGapSpreadMm, kStripeGapShare * std::abs(mean));
  double at_one_gap = 0.0;
  int pairs = 0;
  for_each_pair([&](double gap) {
    if (std::abs(gap - mean) > spread) return;
    at_one_gap += gap;
    ++pairs;
  });
  if (pairs < kMinStripePairs || 2 * pairs < own_bars) return 0.0;
  return 0.5 * at_one_gap / pairs;
}

void LaneDetector::choose_picks(const CameraPose& pose) {
  const CameraModel model(camera_, pose);
  const int n = result_.num_lines;
  int count = 0;
  const int per_line = n > 0 ? config_.max_picks / n : 0;
  const int num_marks = static_cast<int>(result_.marks.size());
  for (int j = 0; j < n; ++j) {
    DetectedLine& line = result_.lines[static_cast<std::size_t>(j)];
    line.first_pick = count;
    // A line of paint hands on its paint only: the blobs grouped with it (a dash's end,
    // a dot beside it) are not where its edges say the line is. A row of dots (its
    // majority kind, as the grouping found) hands on its dots; a row of dots set beside a
    // joint, the joint moved across to where its dots are: the joint is continuous and
    // sharp, so it gives the line's direction and shape better than a few scattered
    // dots; the dots, 5-15 cm beside it, are the marking (and where benchmarks label
    // the line). Left on the joint, the line missed the labels by 20-45 px at 3-6 m. A
    // double line's stripe hands on its bars moved to the double line's middle.
    const bool dots = line.dots;
    const bool joint = line.joints > 0;
    const auto usable_mark = [j, dots, joint](const MarkCandidate& m) {
      return m.line == j && (joint ? m.joint : m.dot == dots && !m.joint);
    };
    const double across = joint ? dots_beside_joint_mm(j) : dots ? 0.0 : double_line_middle_mm(j);
    const auto pick = [&](const MarkCandidate& m) {
      if (across != 0.0)
        if (const std::optional<Vec2> p = model.pixel_from_point(Vec3(m.X, m.Y + across, 0.0)))
          return Pick{j, p->x(), p->y()};
      return Pick{j, m.px(), m.py};
    };
    int usable = 0;
    double joint_near = 1e300, joint_far = -1e300;
    for (const MarkCandidate& m : result_.marks) {
      usable += usable_mark(m);
      if (joint && m.line == j && m.joint) joint_near = std::min(joint_near, m.X), joint_far = std::max(joint_far, m.X);
    }
    // Where the joint does not reach but the line does through its dots (the grouping's
    // reach_through_dots: past a worn, filled or hidden piece of the joint), the dots are
    // the line's only evidence: their own picks, first.
    const auto beyond_the_joint = [&](const MarkCandidate& m) {
      return m.line == j && m.dot && !m.joint && (m.X < joint_near || m.X > joint_far) && m.X >= line.near_mm &&
             m.X <= line.far_mm;
    };
    int beyond = 0;
    if (joint)  // a paint line (most of them) needs no pass for it
      for (const MarkCandidate& m : result_.marks)
        if (beyond < per_line / 4 && beyond_the_joint(m))
          picks_[static_cast<std::size_t>(count + beyond++)] = Pick{j, m.px(), m.py};
    count += beyond;
    // Evenly spread over the line's marks (they come in row order, far to near).
    const int take = std::min(usable, per_line - beyond);
    int seen = 0, next = 0;
    for (int i = 0; i < num_marks && next < take; ++i) {
      const MarkCandidate& m = result_.marks[static_cast<std::size_t>(i)];
      if (!usable_mark(m)) continue;
      if (seen++ == static_cast<int>(static_cast<long>(2 * next + 1) * usable / (2 * take))) {
        picks_[static_cast<std::size_t>(count++)] = pick(m);
        ++next;
      }
    }
    line.num_picks = count - line.first_pick;
  }
  result_.picks = std::span<const Pick>(picks_.data(), static_cast<std::size_t>(count));
}

int LaneDetector::scan(const ImageView& image, const CameraPose& pose, double curvature_per_mm, bool joints) {
  plan_rows(pose, curvature_per_mm, joints);
  const float scale = paint_measure_levels_per_grey(image);
  min_contrast_ = contrast_thresholds(image, {rows_.data(), static_cast<std::size_t>(num_rows_)},
                                      static_cast<float>(config_.min_contrast), scale, row_contrast_);
  const int capacity = static_cast<int>(marks_.size());
  int count = 0;
  scanner_.clear_edges();
  for (int r = 0; r < num_rows_ && count < capacity; ++r)
    count = scanner_.scan(image, rows_[static_cast<std::size_t>(r)], r, row_contrast_[static_cast<std::size_t>(r)],
                          1.0f / scale, marks_.data(), count, capacity);
  // The step test as far out as the picture's blur needs (a blurred edge's ramp is no step).
  if (const int offset = scanner_.step_window_offset(); offset > 0)
    for (int i = 0; i < count; ++i) {
      MarkCandidate& c = marks_[static_cast<std::size_t>(i)];
      c.step_beside = (c.step_beside_at >> offset) & 1;
    }
  return count;
}

bool LaneDetector::on_the_road(MarkCandidate& c) const {
  double X = 0, Y = 0;
  if (!projector_.ground(c.px(), c.py, X, Y) || X < 0.8 * config_.min_range_mm || X > 1.25 * config_.max_range_mm)
    return false;
  c.X = X;
  c.Y = Y;
  return true;
}

std::span<const MarkCandidate> LaneDetector::bars(const ImageView& image, const CameraPose& pose) {
  if (image.empty() || image.width != camera_.Nu || image.height != camera_.Nv) return {};
  // No joints: the vanishing point is found from the lines of paint and markers.
  const int count = scan(image, pose, 0.0, false);
  const float configured = static_cast<float>(config_.min_contrast) * paint_measure_levels_per_grey(image);
  for (int r = 0; r < num_rows_; ++r)
    row_share_[static_cast<std::size_t>(r)] = row_contrast_[static_cast<std::size_t>(r)] / configured;
  return {marks_.data(), static_cast<std::size_t>(count)};
}

int LaneDetector::add_line_in_picture(const ImageView& image, const CameraPose& pose, std::span<const RoadLine> tracked,
                                      int kept, float levels_per_grey) {
  const int n = result_.num_lines;
  if (n < 1 || n >= kMaxDetectedLines) return kept;
  // The nearest line on each side (lines are ordered left to right: largest y0 first).
  int left = -1, right = -1;
  for (int j = 0; j < n; ++j)
    if (result_.lines[static_cast<std::size_t>(j)].fit.y0_mm > 0.0)
      left = j;
    else if (right < 0)
      right = j;
  // A line on each side, two lanes apart or more, and a tracked frame: the line beyond
  // was found on one side, the own lane's line there was not (its dashes held for a step
  // beside them, its dots too few), though the previous frame had it. It is looked for
  // where it was, as when nothing was found on that side, and no nearer the line beyond
  // than a lane's width (TuSimple still 37 held: its right line lost on every tracked
  // frame that found the next lane's). A search's look again does not: on stills of 50-60 m
  // bends the lane it took so was 40-60 mm off where another pose's search put it.
  std::optional<double> widest;
  if (left >= 0 && right >= 0) {
    const double apart = result_.lines[static_cast<std::size_t>(left)].fit.y0_mm -
                         result_.lines[static_cast<std::size_t>(right)].fit.y0_mm;
    if (apart < 2.0 * kMinOwnLaneWidthMm) return kept;
    widest = apart - kMinOwnLaneWidthMm;
  }
  const int nearest = left < 0    ? right
                      : right < 0 ? left
                      : result_.lines[static_cast<std::size_t>(left)].fit.y0_mm <
                              -result_.lines[static_cast<std::size_t>(right)].fit.y0_mm
                          ? left
                          : right;
  const RoadLine beside = result_.lines[static_cast<std::size_t>(nearest)].fit;
  const bool left_found = beside.y0_mm > 0.0;
  const double side = left_found ? -1.0 : +1.0;
  // The previous frame's own line on that side, if it had one a lane's width away.
  std::optional<double> last;
  const OwnLaneLines own = own_lane_lines(tracked);
  const int other = left_found ? own.right : own.left;
  if (other >= 0) {
    const double offset = tracked[static_cast<std::size_t>(other)].y0_mm - beside.y0_mm;
    if (side * offset >= kMinOwnLaneWidthMm && side * offset <= kMaxOwnLaneWidthMm) last = offset;
  }
  if (widest && !last) return kept;  // not a tracked frame's own line (or none to go on)
  // The new line goes right after the line it is looked for beside when that is left of
  // the vehicle, else right before it: the lines stay ordered left to right.
  return look_for_line_in_picture(image, pose, beside, side, left_found ? nearest + 1 : nearest, ChanceRule::clean_road,
                                  kept, levels_per_grey, last, widest);
}

int LaneDetector::add_lines_beyond_in_picture(const ImageView& image, const CameraPose& pose, int kept,
                                              float levels_per_grey) {
  for (const double side : {+1.0, -1.0}) {
    const int n = result_.num_lines;
    if (n >= kMaxDetectedLines) break;
    // Beyond the own lane's line on that side, where nothing was found beyond it.
    int on_side = 0, own = -1;
    for (int j = 0; j < n; ++j)
      if (side * result_.lines[static_cast<std::size_t>(j)].fit.y0_mm > 0.0) ++on_side, own = j;
    if (on_side != 1) continue;
    const DetectedLine& line = result_.lines[static_cast<std::size_t>(own)];
    // A yellow line is the travelled way's edge, and so is a solid white one on the
    // outside (lanes of one direction are parted by broken lines): beyond either lie a
    // shoulder, its edge and a barrier, no lane (LineGrouper::find_lines_beyond's rule for
    // yellow; a shoulder's edge against gravel is a bright strip along the road too). A
    // row of markers is no edge line, and far off, where scan rows lie farther apart than
    // its markers, it has one on every row.
    const bool solid = !line.dots && scan_row_coverage(own, kept) >= kSolidLineCoverage;
    if (line.yellow || solid) continue;
    kept = look_for_line_in_picture(image, pose, line.fit, side, side > 0.0 ? 0 : n, ChanceRule::any_road, kept,
                                    levels_per_grey);
  }
  return kept;
}

double LaneDetector::scan_row_coverage(int j, int kept) const {
  int first = -1, last = -1, rows = 0, previous = -1;
  for (int i = 0; i < kept; ++i) {
    const MarkCandidate& m = marks_[static_cast<std::size_t>(i)];
    if (m.line != j) continue;
    first = first < 0 ? m.scan_row : std::min<int>(first, m.scan_row);
    last = std::max<int>(last, m.scan_row);
    rows += m.scan_row != previous;  // a row's marks are neighbours
    previous = m.scan_row;
  }
  return first < 0 ? 0.0 : static_cast<double>(rows) / (last - first + 1);
}

int LaneDetector::look_for_line_in_picture(const ImageView& image, const CameraPose& pose, const RoadLine& beside,
                                           double side, int index, ChanceRule chance, int kept, float levels_per_grey,
                                           std::optional<double> near_mm, std::optional<double> widest_mm) {
  double from = side > 0.0 ? kMinOwnLaneWidthMm : -kMaxOwnLaneWidthMm;
  const double to = side > 0.0 ? kMaxOwnLaneWidthMm : -kMinOwnLaneWidthMm;
  // Chance is measured across every lane width; the line is taken only where `taken` says.
  std::optional<PictureLineSearch::Window> taken;
  if (widest_mm) {  // no farther than this from `beside`
    taken = side > 0.0 ? PictureLineSearch::Window{from, std::min(to, *widest_mm)}
                       : PictureLineSearch::Window{std::max(from, -*widest_mm), to};
  }
  // Near its last place, with a candidate on that place (the grid of candidates starts a
  // whole number of steps from it): a line a few hits above the minimum is found where it
  // was last found.
  if (near_mm) {
    const PictureLineSearch::Window near{*near_mm - kTrackedWindowMm, *near_mm + kTrackedWindowMm};
    taken = taken
                ? PictureLineSearch::Window{std::max(taken->from_mm, near.from_mm), std::min(taken->to_mm, near.to_mm)}
                : near;
    from =
        *near_mm - std::floor((*near_mm - from) / PictureLineSearch::kOffsetStepMm) * PictureLineSearch::kOffsetStepMm;
  }
  const PictureLine& found =
      picture_line_.find(image, pose, beside, from, to, config_.min_range_mm, config_.max_range_mm,
                         config_.mark_width_mm, static_cast<double>(min_contrast_), chance, taken);
  if (!found.found || kept + found.hits > static_cast<int>(marks_.size())) return kept;
  const int n = result_.num_lines;
  for (int j = n; j > index; --j)
    result_.lines[static_cast<std::size_t>(j)] = result_.lines[static_cast<std::size_t>(j - 1)];
  for (int i = 0; i < kept; ++i)
    if (marks_[static_cast<std::size_t>(i)].line >= index) ++marks_[static_cast<std::size_t>(i)].line;
  DetectedLine line;
  line.fit = beside;
  line.fit.y0_mm += found.offset_mm;
  line.marks = found.hits;
  line.parallel = true;
  line.in_picture = true;
  line.near_mm = 1e300, line.far_mm = 0.0;
  for (const PictureLineHit& h : found.marks) {
    MarkCandidate m;
    m.left_px = h.px - h.half_width_px;
    m.right_px = h.px + h.half_width_px;
    m.py = h.py;
    m.contrast = h.contrast / static_cast<double>(levels_per_grey);
    m.X = h.X;
    m.Y = h.Y;
    m.line = static_cast<std::int16_t>(index);
    m.scan_row = static_cast<std::int16_t>(h.row);
    marks_[static_cast<std::size_t>(kept++)] = m;
    line.near_mm = std::min(line.near_mm, h.X);
    line.far_mm = std::max(line.far_mm, h.X);
  }
  result_.lines[static_cast<std::size_t>(index)] = line;
  ++result_.num_lines;
  return kept;
}

const DetectionResult& LaneDetector::detect(const ImageView& image, const CameraPose& pose,
                                            std::span<const RoadLine> priors, PictureSearch picture_search,
                                            bool bend_confirmed) {
  result_ = DetectionResult{};
  if (image.empty() || image.width != camera_.Nu || image.height != camera_.Nv) return result_;
  double mean_m = 0.0, mean_c = 0.0;
  for (const RoadLine& p : priors) {
    mean_m += p.m / static_cast<double>(priors.size());
    mean_c += p.c_per_mm / static_cast<double>(priors.size());
  }
  const int count = scan(image, pose, mean_c, true);
  have_vp_ = projector_.vanishing_point(mean_m, vp_x_, vp_y_);
  road_m_ = mean_m;
  // The tangent's point (points_to_vanishing_point) from a curvature the previous frame's
  // lane had; a search's first solve, which a look again starts from, has its curvature
  // from a few marks, and lines tracked without a lane may be clutter's.
  // Only a bend sharper than kTangentRadiusMm: on a gentler one the straight road's point
  // is within a few degrees of every tangent's in the searched range, and the tangent of
  // a slightly wrong curvature (a word taken for a line) lets other bars in.
  road_c_per_mm_ = bend_confirmed && bends_sharper_than_tangent_radius(mean_c) ? mean_c : 0.0;
  const float scale = paint_measure_levels_per_grey(image);
  result_.counters.scan_rows = num_rows_;
  result_.counters.candidates = count;

  // What cannot be paint on the road: off the road plane or the searched range, or a bar
  // that does not run towards the vanishing point (shadow edges, car parts, seams).
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    MarkCandidate c = marks_[static_cast<std::size_t>(i)];
    if (!on_the_road(c)) {
      ++result_.counters.off_road;
      continue;
    }
    if (c.joint) {  // its direction is keep_linked_joints' to judge
      marks_[static_cast<std::size_t>(kept++)] = c;
      continue;
    }
    c.dot = c.shadow_side != 0 ? is_shadowed_dot(image, c, scale) : is_dot(image, c, scale);
    if (c.narrow && !c.dot) {
      ++result_.counters.narrow;
      continue;
    }
    c.yellow = !c.dot && is_yellow(image, c);
    // A step beside a bar biases its edges, unless the bar is yellow paint: on pale
    // concrete the step beside yellow paint is its own colour bled into its sides (colour
    // is sampled at half the resolution and blurred again by video codecs), the same on
    // either side, and the bar's centre stays where the paint is. Barrier feet, kerbs,
    // seams and slab edges, whose steps do bias, are grey.
    // Such a bar is held for a line beyond the road's others (lane_marks.hpp,
    // for_lines_beyond); a marker's cap beside its shadow that is no marker is no line's.
    if (c.step_beside && !c.dot && !c.yellow) {
      ++result_.counters.step_beside;
      if (c.shadow_side != 0) continue;
      c.for_lines_beyond = true;
    }
    if (!c.dot && !points_to_vanishing_point(image, c)) {
      ++result_.counters.wrong_orientation;
      continue;
    }
    if (!c.dot && !c.yellow && between_beads(image, c)) {
      ++result_.counters.between_beads;
      continue;
    }
    result_.counters.dots += c.dot;
    result_.counters.yellow += c.yellow;
    marks_[static_cast<std::size_t>(kept++)] = c;
  }
  kept = keep_one_sun(kept);
  kept = keep_linked_joints(kept);
  kept = drop_crossings(kept);
  const std::span<MarkCandidate> marks(marks_.data(), static_cast<std::size_t>(kept));
  GroupingParams params;
  params.min_marks = config_.min_marks;
  params.max_lines = config_.max_lines;
  params.mm_per_px_per_mm = camera_.pitch_u() / pose.f_mm;
  params.height_mm = pose.H_mm;
  // Without lines to go on, the pose is a search's guess (detection_config.hpp).
  if (priors.empty()) params.max_pitch_error_rad = deg_to_rad(kSearchPitchErrorDeg);
  params.tracked_priors = !priors.empty() && picture_search == PictureSearch::own_lane;
  result_.num_lines = grouper_.group(marks, priors, params, result_.lines);
  // The held bars no line beyond took are nothing of the road's.
  int grouped = 0;
  for (const MarkCandidate& m : marks)
    if (!m.for_lines_beyond || m.line >= 0) marks_[static_cast<std::size_t>(grouped++)] = m;
  // The own lane's other line in the picture only from a pose a solve gave (a search's
  // look again, or the previous frame's): from a guessed pose, a lane's width across says
  // little of where in the picture that line runs.
  if (!priors.empty()) {
    const bool tracked = picture_search == PictureSearch::own_lane;
    grouped = add_line_in_picture(image, pose, tracked ? priors : std::span<const RoadLine>{}, grouped, scale);
    if (picture_search == PictureSearch::own_lane_and_beyond)
      grouped = add_lines_beyond_in_picture(image, pose, grouped, scale);
  }
  result_.marks = std::span<const MarkCandidate>(marks_.data(), static_cast<std::size_t>(grouped));
  for (const MarkCandidate& m : result_.marks) result_.counters.grouped += m.line >= 0;
  choose_picks(pose);
  return result_;
}

}  // namespace ccdlane
