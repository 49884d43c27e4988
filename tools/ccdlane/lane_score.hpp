// Scoring reported lane lines against a lane annotation in image space, by TuSimple's
// rules (docs/interfaces.md "Scoring against annotations"): `ccdlane score` per frame.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/lane_marks.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane::cli {

// One annotated lane of a frame: its grey level in the mask and, on every row it
// covers, the centre of its pixels (1-based column, 1-based row).
struct AnnotatedLane {
  int level = 0;  // the mask's grey level, or the label's index
  std::vector<Vec2> points;
  // TuSimple's threshold for this lane, 1 / cos of its angle to the picture's vertical
  // (a slanted lane's points are farther apart along a row): the rules' threshold is
  // multiplied by it. 1 for masks, whose lanes are scored on rows as they are.
  double threshold_scale = 1.0;
  bool ego = false;  // one of the own lane's two lines (mark_ego_lanes)
  // Where the lane, extended by a straight line through its lowest points, crosses the
  // picture's bottom row (1-based column; mark_ego_lanes): which side of the vehicle it
  // is on, and how far out.
  double x_bottom = 0.0;
};

// The lanes of an 8-bit grey mask: each grey level other than 0 is one lane. Ego lanes
// are marked.
std::vector<AnnotatedLane> lanes_of_mask(const ImageView& mask);

// 1 / cos of the lane's angle to the vertical, from a least-squares line x = a + k y
// through its points (TuSimple's get_angle): 1 for fewer than two points.
double tusimple_threshold_scale(const AnnotatedLane& lane);

// Marks the own lane's two lines: where each lane's lowest points, extended by a
// straight line to the picture's bottom row, cross it, the nearest left and the nearest
// right of the picture's centre column (the vehicle's lane, as lane benchmarks take it).
void mark_ego_lanes(std::span<AnnotatedLane> lanes, int width, int height);

struct ScoreRules {
  double threshold_px = 20.0;    // at 1280 pixels wide; scaled by width / 1280
  double found_fraction = 0.85;  // of a lane's points hit: the lane is found
  double true_fraction = 0.85;   // of a reported line's points on a lane: not false
  // The reported line is its model y0 + m x + c x^2 over this stretch of road ahead.
  double near_mm = 500.0;
  double far_mm = 300000.0;
  static double threshold_for_width(double threshold_at_1280, int width) { return threshold_at_1280 * width / 1280.0; }
  // Whether a lane of `points` points, `hits` of them hit by one line, is found.
  bool lane_found(std::size_t hits, std::size_t points) const {
    return points > 0 && static_cast<double>(hits) >= found_fraction * static_cast<double>(points);
  }
};

struct FrameScore {
  int lanes = 0;                           // annotated
  int found = 0;                           // of them, found
  int reported = 0;                        // lines reported (in the picture on annotated rows)
  int false_lines = 0;                     // of them, on no lane
  std::size_t points = 0, hit_points = 0;  // annotated lane points, and those hit
  int ego_lanes = 0, ego_found = 0;        // the same for the own lane's two lines
  std::size_t ego_points = 0, ego_hit_points = 0;

  FrameScore& operator+=(const FrameScore& o);
};

// Scores the lines reported at `camera`'s pose against the lanes of a mask `width` wide.
// A lane point is hit by a line passing within the threshold (times the lane's
// threshold_scale) on its row; a lane counts
// the hits of the line that hits most of its points, and is found with found_fraction
// of them. A line's points are its columns on every row where some lane has a point
// (and the line is in the picture); it is false when fewer than true_fraction of them
// are within the threshold of a lane point on that row. A line on no annotated row is
// neither counted nor false.
// `point_hits`, when given, gets per lane (in `lanes`' order) the line that hits most of
// its points, which of them it hits and by how far it passes each, in the lane's point
// order: what an overlay shows, and whether a lost lane's line misses it inside or
// outside, near the car or far.
// `line_results`, when given, gets per reported line (in `lines`' order) its points, those
// on a lane, and the rows (1-based) where it is on none: where a false line leaves the
// lanes, near or far.
struct LaneHits {
  int line = -1;          // the reported line that hits most of the lane's points; -1: none hits one
  std::vector<bool> hit;  // per point: hit by that line
  // Per point: that line's column on the point's row minus the point's (pixels, + is
  // right); empty where the line does not cross that row within the picture, or there is
  // no such line.
  std::vector<std::optional<double>> offset_px;
};
using LanePointHits = std::vector<LaneHits>;
struct ReportedLineResult {
  std::size_t points = 0, on_lane = 0;  // no points: on no annotated row, not counted
  bool false_line = false;
  std::vector<int> off_rows;
};
FrameScore score_frame(std::span<const AnnotatedLane> lanes, int width, const CameraModel& camera,
                       std::span<const RoadLine> lines, const ScoreRules& rules = {},
                       LanePointHits* point_hits = nullptr, std::vector<ReportedLineResult>* line_results = nullptr);

// TuSimple's own benchmark on one labelled picture (LaneEval.bench of its lane.py), for
// comparison with published figures: each line and lane is sampled at every labelled row
// (no point: -2); a lane's accuracy with a line is the share of all the rows where both
// have no point or the line is within the lane's threshold of it (a point of one where
// the other has none is a miss); each lane takes its best line, and is matched with
// found_fraction of its rows. accuracy: the lanes' best accuracies summed (beyond four
// lanes, less the worst) over min(4, lanes); fp: the lines not matching a lane, over the
// lines; fn: the lanes without a match (beyond four lanes, one fewer), over min(4, lanes).
// More than two lines more than lanes scores 0, 0, 1, as TuSimple's does.
struct LaneEvalScore {
  double accuracy = 0.0, fp = 0.0, fn = 0.0;
};
LaneEvalScore lane_eval_frame(std::span<const AnnotatedLane> lanes, std::span<const double> rows, int width,
                              const CameraModel& camera, std::span<const RoadLine> lines, const ScoreRules& rules = {});

}  // namespace ccdlane::cli
