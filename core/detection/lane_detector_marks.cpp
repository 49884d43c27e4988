// Which of the row filter's candidates are what (lane_detector.hpp): bars that run
// towards the road's vanishing point, Botts' dots and raised markers (lit caps and their
// shadows), the sun's side, crossings' stripes, joints linked along the road, bars
// between a sealed crack's beads, yellow paint.
#include <algorithm>
#include <cmath>

#include "core/detection/detection_rules.hpp"
#include "core/detection/lane_detector.hpp"
#include "core/detection/paint_measure.hpp"

namespace ccdlane {

using namespace detection_rules;

namespace {

constexpr double kOrientationTolerance = 0.5;  // sin(30 deg): between a bar and the way to the vanishing point
constexpr double kMaxDotWidthMm = 250.0;
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
// A joint's piece on the next scan row lies within this (plus half their widths) of where
// the line from the vanishing point through it crosses that row.
constexpr double kJointLinkPx = 1.5;
// Yellow paint stands above the road mostly by its colour (on pale concrete, by its
// colour alone): its yellowness is at least this fraction of its contrast, and above
// the tint of grey surfaces (a few levels) by this much. White paint's is near 0.
constexpr double kYellowShareOfContrast = 0.5;
constexpr int kMinYellowness = 20;

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

// How many pixels of row yy, columns xa to xb, are `so`.
template <typename Test>
int count_so(int xa, int xb, int yy, const Test& so) {
  int n = 0;
  for (int x = xa; x <= xb; ++x) n += so(x, yy);
  return n;
}

}  // namespace

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

}  // namespace ccdlane
