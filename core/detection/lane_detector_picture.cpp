// The lines detection looks for along their length in the picture (line_in_picture.hpp),
// beside the lines the road plane gave: the own lane's other line, and the next lanes'.
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/detection/lane_detector.hpp"

namespace ccdlane {

namespace {

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

}  // namespace

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

}  // namespace ccdlane
