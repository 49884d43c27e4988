// The [detection] table: what lane-mark detection looks for and where.
#pragma once

namespace ccdlane {

constexpr int kMaxDetectedLines = 4;  // = kMaxLaneLines of the solver
// How far off in pitch a pose detection is given without lines to go on may be: a search
// tries poses this far apart (LaneEstimator::kSearchPitchStepDeg) and the vanishing point
// is found to a degree or two.
constexpr double kSearchPitchErrorDeg = 4.0;

struct DetectionConfig {
  double mark_width_mm = 130.0;      // expected lane-mark width on the road
  double min_mark_width_mm = 100.0;  // narrowest and widest paint taken for a lane mark:
  double max_mark_width_mm = 300.0;  // wider bars are barrier feet, text, arrows, patches
  double min_contrast = 10.0;        // grey levels (8-bit scale) paint stands above both sides
  double min_range_mm = 3000.0;      // nearest road distance searched (also: below it, the hood)
  double max_range_mm = 40000.0;     // farthest
  int roi_top_px = 0;                // picture rows never searched: at the top (sky, a sun visor)
  int hood_px = 0;                   // and at the bottom (the vehicle's hood, a dashboard)
  int max_lines = 4;                 // lane lines reported, 2..4
  int max_picks = 240;               // picks per frame handed to the solver
  int min_marks = 8;                 // picks a line needs to count as found
  double departure_mm = 900.0;       // warn when a line of the own lane is nearer than this
                                     // to the vehicle's centre (half a car plus a margin)

  bool operator==(const DetectionConfig&) const = default;
};

}  // namespace ccdlane
