// Scoring reported lane lines against a lane annotation in image space, by TuSimple's
// rules (docs/interfaces.md "Scoring against annotations"): `ccdlane score` per frame.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/lane_marks.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane::cli {

// One annotated lane of a frame: its grey level in the mask and, on every row it
// covers, the centre of its pixels (1-based column, 1-based row).
struct AnnotatedLane {
  int level = 0;
  std::vector<Vec2> points;
};

// The lanes of an 8-bit grey mask: each grey level other than 0 is one lane.
std::vector<AnnotatedLane> lanes_of_mask(const ImageView& mask);

struct ScoreRules {
  double threshold_px = 20.0;    // at 1280 pixels wide; scaled by width / 1280
  double found_fraction = 0.85;  // of a lane's points hit: the lane is found
  double true_fraction = 0.85;   // of a reported line's points on a lane: not false
  // The reported line is its model y0 + m x + c x^2 over this stretch of road ahead.
  double near_mm = 500.0;
  double far_mm = 300000.0;
  static double threshold_for_width(double threshold_at_1280, int width) { return threshold_at_1280 * width / 1280.0; }
};

struct FrameScore {
  int lanes = 0;                           // annotated
  int found = 0;                           // of them, found
  int reported = 0;                        // lines reported (in the picture on annotated rows)
  int false_lines = 0;                     // of them, on no lane
  std::size_t points = 0, hit_points = 0;  // annotated lane points, and those hit
};

// Scores the lines reported at `camera`'s pose against the lanes of a mask `width` wide.
// A lane point is hit by a line passing within the threshold on its row; a lane counts
// the hits of the line that hits most of its points, and is found with found_fraction
// of them. A line's points are its columns on every row where some lane has a point
// (and the line is in the picture); it is false when fewer than true_fraction of them
// are within the threshold of a lane point on that row. A line on no annotated row is
// neither counted nor false.
FrameScore score_frame(std::span<const AnnotatedLane> lanes, int width, const CameraModel& camera,
                       std::span<const RoadLine> lines, const ScoreRules& rules = {});

}  // namespace ccdlane::cli
