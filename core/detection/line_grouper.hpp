// Groups lane-mark candidates into lane lines on the road: first along the lines the
// previous frame found (gated), then new lines from a Hough vote over (y0, m) among the
// candidates left, each refined by a trimmed least-squares fit.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/detection/lane_marks.hpp"

namespace ccdlane {

struct GroupingParams {
  int min_marks = 8;            // candidates a line needs
  double min_span_mm = 3000.0;  // and the road distance they must cover
  int max_lines = 4;
  // Two lines nearer than this (at 10 m) are one, or one of them is no lane line: no lane
  // is narrower (kMinLaneWidthMm). Arrows and words sit 1.8 m from the lines beside them.
  double min_separation_mm = 2500.0;
  // Lateral road distance one pixel spans, per mm of distance (about pitch_u / f): the
  // final fits keep marks within fit_tolerance_px of the line.
  double mm_per_px_per_mm = 1.0 / 600.0;
  double fit_tolerance_px = 2.0;
  // Scatter about the final fit: paint is sharp, clutter is not. Uniform clutter within
  // the tolerance scatters 1.15; worn paint, yellow on concrete and rows of raised
  // markers seen far away as bars scatter up to about 1 (segB, TuSimple).
  double max_rms_px = 1.1;
  double min_coverage = 0.12;  // marks per scan row over the rows a line spans (dashes ~0.25)
  // A line of Botts' dots or raised markers (1-3 m apart, each seen on a row or three)
  // covers fewer rows than paint: it counts when this many separate dots lie on it.
  int min_dots = 6;
  // A row of dots parallel to the lines found (their slope and curvature, y0 alone
  // fitted) counts with fewer: the road's lines say where it runs, and the near and far
  // ends of the searched range often hold a group or two of a few dots each.
  int min_parallel_dots = 4;
  // A row of dots set along a joint between concrete slabs counts with fewer still: the
  // joint, straight and along the road, is where the line runs between its dots. A joint
  // without dots on it is a seam, and no line.
  int min_joint_dots = 3;
  // A line parallel to the lines found (the road's slope and curvature at its y0), or
  // continuing a previous frame's line, is found from less: one dash of a dashed line on
  // a bend, whose others are in the gaps or beyond the range (3 m dashes, 9 m gaps).
  int min_dash_marks = 5;
  double min_dash_span_mm = 1000.0;
  // The lines of one road meet at one vanishing point: on the road, as the detection pose
  // projects them, their slopes differ only as much as a pitch error tilts them (by their
  // lateral distance times the error over the camera's height). A new line whose slope
  // is farther from the road's direction at its place than that, plus a little for
  // edge noise, is a car's side, an arrow's stroke or a shadow, not a lane line.
  double max_pitch_error_rad = 0.026;  // 1.5 degrees: tracking; a search is less sure
  double height_mm = 1200.0;           // the detection pose's
  double slope_noise = 0.01;
  // The priors are a tracked frame's (the previous frame's lines), not a search's own
  // first solve: a line continuing one may miss its fit smoothly (line_grouper.cpp,
  // kSmoothMisfitRmsScale). continuing_tracked_line: fit_line is continuing one.
  bool tracked_priors = false;
  bool continuing_tracked_line = false;
};

// The slope of log(width px) against log(road distance) over the marks of line `line`
// that are dots (`dots`) or paint: about -1 for things of one size on the road, which
// narrow with distance. NaN with fewer than 3 such marks or all at one distance.
double width_distance_slope(std::span<const MarkCandidate> marks, int line, bool dots);

class LineGrouper {
 public:
  // The Hough accumulator and index buffers for up to max_marks candidates are allocated
  // here; group() allocates nothing.
  explicit LineGrouper(int max_marks);

  // Assigns marks[i].line and fills lines (returns how many), ordered left to right
  // (largest y at 10 m first). `priors` are the previous frame's lines; a line continuing
  // prior k has prior_index k. Picks are not chosen here.
  int group(std::span<MarkCandidate> marks, std::span<const RoadLine> priors, const GroupingParams& params,
            std::array<DetectedLine, kMaxDetectedLines>& lines);

  static constexpr int kY0Bins = 300;    // -15 m .. 15 m in 100 mm
  static constexpr int kSlopeBins = 41;  // -0.25 .. 0.25
  static constexpr int kRansacIterations = 48;
  static constexpr int kMaxFoundLines = 8;  // searched for, before the nearest are kept
  // A row of dots found as a parallel of the others fits its own slope (not its
  // curvature) when its marks span this much road: two of its groups. Paint found so does
  // not: the dashes of one line and an arrow's or a word's strokes beside it, each
  // parallel to the road, would make a slanted line together.
  static constexpr double kOwnSlopeSpanMm = 6000.0;

 private:
  // Gathers the free (or `line`-assigned) marks in the gate around `model`, finds their
  // consensus line (RANSAC), refits by least squares; assigns the marks to `line`.
  // `parallel`: keep the model's slope and curvature (those of the road's other lines, or
  // of the line's previous frame), fit y0 alone (and the slope when the marks span 6 m),
  // and accept a single dash or a few dots; a row of dots may then take a slope up to
  // `slope_freedom` from the model's (beside a single line, what a pitch error tilts).
  bool fit_line(std::span<MarkCandidate> marks, RoadLine model, double gate_base_mm, int line,
                const GroupingParams& params, DetectedLine& out, bool parallel = false, double slope_freedom = 0.0);
  // fit_line's steps: the marks in the gate (indices in gated_), their consensus line,
  // and one least-squares pass over the marks within `tolerance` fit tolerances of
  // `model`, which it refits (assigning them to `id`).
  struct FitPass {
    int marks = 0;
    double near_mm = 1e300, far_mm = 0.0;  // the road distances the marks span
    int rows = 0;                          // scan rows from the first mark's to the last's
    int dots = 0;                          // separate dots among the marks
    int dot_marks = 0, yellow_marks = 0;   // marks that are dots, yellow paint
    bool finite = true;                    // the refit is a number
  };
  int gate_marks(std::span<const MarkCandidate> marks, const RoadLine& model, double gate_base_mm, std::int16_t id);
  RoadLine consensus_line(std::span<const MarkCandidate> marks, int gated, const RoadLine& model, int line,
                          const GroupingParams& params, bool parallel, double slope_freedom) const;
  // One least-squares pass over the free marks within `tolerance` pixel tolerances of
  // `model`, refitting it. Marks too short a stretch of road to show a curvature keep
  // `road_c_per_mm`, the curvature the line was looked for along.
  FitPass fit_pass(std::span<MarkCandidate> marks, RoadLine& model, std::int16_t id, const GroupingParams& params,
                   double tolerance, bool parallel, bool dot_line, double road_c_per_mm);
  // A row of dots too few for a line of their own, set beside a joint between concrete
  // slabs: the joint within kJointBandMm of the dots' line `model`, fitted, is the line
  // when it is one (min_marks pieces over min_span_mm, within the fit's tolerance, whose
  // pixels are never finer than a 1150 px focal length's: a joint's scatter is the
  // road's) and keeps min_dots of the dots beside it. Assigns the joint and those dots to `id`.
  bool join_joint(std::span<MarkCandidate> marks, RoadLine model, std::int16_t id, const GroupingParams& params,
                  double min_span_mm, const RoadLine& looked_for, double gate_base_mm, DetectedLine& out, int min_dots);
  // The own lane's missing line as a joint alone: where the n lines found lie on one side
  // of the vehicle only, a joint along the road a lane's width from the nearest of them
  // on the other side, found as join_joint finds one, with or without dots.
  int find_own_joint(std::span<MarkCandidate> marks, const GroupingParams& params, int n);

  // group()'s steps, each taking and returning how many lines found_ holds.
  int continue_priors(std::span<MarkCandidate> marks, std::span<const RoadLine> priors, const GroupingParams& params);
  int find_new_lines(std::span<MarkCandidate> marks, std::span<const RoadLine> priors, const GroupingParams& params,
                     int n);
  int find_dashes(std::span<MarkCandidate> marks, std::span<const RoadLine> priors, const GroupingParams& params,
                  int n);
  // One line more on each side, beyond the outermost of the n found and parallel to them,
  // where free marks and those held for it (MarkCandidate::for_lines_beyond) agree on a y0.
  int find_lines_beyond(std::span<MarkCandidate> marks, std::span<const RoadLine> priors, const GroupingParams& params,
                        int n);
  // Whether one of the n lines found continues prior k.
  bool continues_prior(int k, int n) const;
  // A line parallel to the road's (`model`, the road's line through where it is looked
  // for), fitted as such (y0, and the slope over 6 m) and admitted among the n found;
  // it continues prior `prior_index` (-1: none). `beyond_y_mm`: where the outermost line
  // found lies (at the reference distance) when it is looked for beyond it
  // (find_lines_beyond), NaN otherwise. Whether it was taken.
  bool add_parallel(std::span<MarkCandidate> marks, const GroupingParams& params, int& n, const RoadLine& model,
                    int prior_index, double beyond_y_mm = std::numeric_limits<double>::quiet_NaN());
  int keep_nearest(std::span<MarkCandidate> marks, const GroupingParams& params, int n,
                   std::array<DetectedLine, kMaxDetectedLines>& out) const;
  // Drops the rows of dots among the n lines that lie beyond a yellow line, however they
  // were found (a line of its own from the vote, a prior continued): blobs of a
  // shoulder or a barrier's foot. Their marks are freed; the lines left keep their order.
  int drop_dots_beyond_yellow(std::span<MarkCandidate> marks, int n);
  // Drops the lines `drop` marks among the n found, keeps the others in order and
  // renumbers their marks (a dropped line's are freed); returns how many are left.
  int drop_lines(std::span<MarkCandidate> marks, int n, const std::array<bool, kMaxFoundLines>& drop);
  // Adds `l` (its marks assigned to line n) to the n lines found when it is
  // min_separation_mm from each; or puts it in the place of the lines it is too near when
  // it is the better evidence of a line than each (paint over a row of dots, yellow paint
  // over grey bars, or far more marks). Otherwise releases its marks. Whether it was
  // taken.
  bool admit(std::span<MarkCandidate> marks, const DetectedLine& l, int& n, const GroupingParams& params);
  // Whether a line at `y` (at the reference distance) lies beyond a yellow line found
  // among the first n, on the same side of the vehicle. A yellow line is the travelled
  // way's edge (its left edge on divided roads): beyond it lie a shoulder, a barrier's
  // foot and its blobs, no lane. Refused for it: a row of dots found from a few of them
  // along the road's direction, a joint taken as the own lane's line, a line beyond.
  bool beyond_a_yellow_line(double y, int n) const;
  // The curvature the lines found so far share (weighted by marks), else the priors' mean.
  double shared_curvature(std::span<const RoadLine> priors, int n) const;
  // The votes' strongest cell (bi, bj) and its votes.
  int strongest_cell(int& bi, int& bj, int min_joint_dots) const;
  int strongest_cell_own_votes(int bi, int bj) const;  // a cell's votes of paint and dots
  void revote(std::span<const MarkCandidate> marks);
  void vote(const MarkCandidate& m, int delta);

  std::vector<std::uint16_t> votes_;        // kY0Bins x kSlopeBins: paint and dots
  std::vector<std::uint16_t> joint_votes_;  // and joints
  int joint_votes_cast_ = 0;                // joints voting
  std::vector<int> gated_;                  // indices of the marks inside a line's gate
  double curvature_ = 0.0;                  // c the votes are cast along
  std::array<DetectedLine, kMaxFoundLines> found_{};
};

}  // namespace ccdlane
