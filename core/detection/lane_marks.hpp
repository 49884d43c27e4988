// What detection works with and hands on: lane-mark candidates found along image rows,
// lane lines grouped from them on the road, and the labelled picks for the solver.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "core/detection/detection_config.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane {

// A bright bar between two darker sides on one image row: a piece of paint, perhaps.
struct MarkCandidate {
  double left_px = 0, right_px = 0;  // sub-pixel edges along the row, 1-based observed
  double py = 0;                     // the row, 1-based
  double contrast = 0;               // paint minus the darker side, grey levels (8-bit scale)
  double X = 0, Y = 0;               // where the centre lies on the road at the detection pose, mm
  std::int16_t line = -1;            // index of the line it was grouped into, -1 = none
  std::int16_t scan_row = 0;         // which scan row found it
  // A short blob rather than a piece of a long bar: a Botts' dot or raised pavement
  // marker (about 10 cm across, 1-3 m apart), or a dash's very end. Its edges are round,
  // so they say nothing of the line's direction.
  bool dot = false;
  // A dot's own rows (1-based, first and last lit along its centre column): marks of
  // one dot found on several scan rows share them.
  std::int16_t dot_top = 0, dot_bottom = 0;
  // Another step within the row filter's reach beside the bar (a shadow border, a patch,
  // a dash's end, a raised marker's shadow): its edges may be pulled by up to half the
  // filter's width.
  bool step_beside = false;
  // The step test read with its windows 0, 1 and 2 pixels farther from the bar's edges
  // (bit k: a step beside at k pixels): a blurred picture's edges ramp over more pixels
  // than the test's window allows for, and the frame's measured blur says which to take
  // (MarkScanner::step_window_offset).
  std::uint8_t step_beside_at = 0;
  // A bar with such a step that is neither a dot nor yellow paint: its edges may be
  // pulled, and barrier feet, kerbs and slab edges look so, so it founds no line of its
  // own and joins none the road's lines are found by. A line one lane beyond them may
  // take it: an edge line beside a shoulder of another surface has a step beside it all
  // along (LineGrouper::find_lines_beyond). Marks of it that join no line are dropped.
  bool for_lines_beyond = false;
  // Narrower than paint (ScanRow::min_dot_width_px): taken only if it is a dot; a long
  // bar that narrow is a crack's edge, a wire or a seam's lip.
  bool narrow = false;
  // Yellow paint: its colour is most of what it stands above the road by. Barrier feet,
  // kerbs, seams and concrete are grey; a yellow line is paint.
  bool yellow = false;
  // A dark line narrower than paint between two sides of one level: the sealed joint
  // between concrete slabs, which on concrete roads runs along the lane lines, and along
  // which their raised markers are set. Never a line of its own (seams, cracks and tar
  // lines run everywhere): it joins a row of markers (line_grouper.hpp).
  bool joint = false;
  // A raised marker found as a lit cap beside its own shadow (dot_scanner.hpp): the side
  // the shadow lies on (+1 right, -1 left; 0: not found so) and its width, pixels.
  std::int8_t shadow_side = 0;
  float shadow_px = 0.0f;

  double px() const { return 0.5 * (left_px + right_px); }
  double width_px() const { return right_px - left_px; }
};

struct DetectedLine {
  RoadLine fit;        // the line as detection fitted it, at the detection pose
  int marks = 0;       // candidates grouped into it
  int first_pick = 0;  // its picks: DetectionResult::picks[first_pick .. + num_picks)
  int num_picks = 0;
  double near_mm = 0.0;  // the road distances it was seen over
  double far_mm = 0.0;
  double rms_mm = 0.0;    // lateral scatter of its marks about the fit
  int prior_index = -1;   // the prior line it continues, -1 = newly found
  bool parallel = false;  // found as a parallel of the road's other lines (y0 alone fitted,
                          // and its slope when its marks span 6 m)
  bool dots = false;      // most of its marks are dots (a row of raised markers)
  int joints = 0;         // of its marks, pieces of the joint its markers are set along
  bool yellow = false;    // most of its marks are yellow paint
  // Found along its length in the picture, a lane's width from a line found: the own
  // lane's other line, or the next lane's beyond (line_in_picture.hpp): its marks lie in
  // several places over many metres of road, more of them than chance puts on any line
  // there.
  bool in_picture = false;
};

// Counts of what the row filter found and why candidates were dropped.
struct DetectionCounters {
  int scan_rows = 0;
  int candidates = 0;         // dark-bright-dark bars of a plausible width and contrast
  int off_road = 0;           // above the horizon or out of the searched range
  int wrong_orientation = 0;  // not running towards the road's vanishing point
  int step_beside = 0;        // a bar (not a dot) whose edges a step beside it may bias: held
                              // for a line beyond the road's others (for_lines_beyond), else dropped
  int narrow = 0;             // a bar (not a dot) narrower than paint
  int dots = 0;               // short blobs (Botts' dots, raised markers) among those kept
  int against_the_sun = 0;    // markers whose shadow falls the other way than most (dropped)
  int joints = 0;             // joints between slabs among those kept
  int crossing_bars = 0;      // bars side by side across the road on a row: a crossing's (dropped)
  int between_beads = 0;      // bars between a sealed crack's two beads: the road's own (dropped)
  int yellow = 0;             // yellow paint among those kept
  int grouped = 0;            // on a reported line
};

struct DetectionResult {
  int num_lines = 0;  // ordered left to right as seen from the vehicle (largest y0 first)
  std::array<DetectedLine, kMaxDetectedLines> lines{};
  std::span<const Pick> picks;           // labelled 0..num_lines-1 in that order
  std::span<const MarkCandidate> marks;  // every candidate kept after the row filter
  DetectionCounters counters;
};

}  // namespace ccdlane
