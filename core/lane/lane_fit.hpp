// The fit stage of the lane estimator: a detection's picks and lines solved for the
// attitude and the lines on the road (gyro roll and pitch as priors), the picks and lines
// that do not fit dropped, and the solved lane checked for the support a real one gives.
#pragma once

#include <algorithm>
#include <array>
#include <optional>
#include <span>
#include <vector>

#include "base/gx1_angles.hpp"
#include "core/detection/lane_marks.hpp"
#include "core/lane/lane_estimator_options.hpp"
#include "core/lane/lane_support.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane {

// What the own lane is, as the track stage found it (indices into the solve's lines) and
// measured it: what lane_support_problem() checks.
struct OwnLane {
  int left = -1, right = -1;
  double lane_width_mm = 0.0;
  double heading_deg = 0.0;
  double curvature_per_m = 0.0;
};

class LaneFit {
 public:
  // Sizes the solver and the pick buffers for options.detection.max_picks. May allocate.
  explicit LaneFit(const LaneEstimatorOptions& options);

  // Takes a detection's picks and lines as the problem to solve; false when they are too
  // few to solve (the frame has too_few_marks). `own_priors`: the lines detection looked
  // along were this frame's own solve's, not a previous frame's (no line continues one).
  bool take(const DetectionResult& detection, bool own_priors = false);

  // Solves the problem taken, from `initial`; `gyro` gives roll and pitch priors.
  const SolveResult& solve(const CameraPose& initial, const std::optional<Gx1Angles>& gyro);
  // The roll the tracked frame before solved, and how far the camera may have rolled
  // since (lane_estimator.hpp, kRollWalkDegPerSqrtS): without a gyro, a solve whose lines
  // continue a track holds its roll by it as well as by the configured prior. Nullopt:
  // none (a search, the first frame).
  void set_previous_roll(const std::optional<Prior>& roll) { previous_roll_ = roll; }

  // After a converged solve that fits badly: drops the lines and then the picks that miss
  // their marks, keeping the solved lines as the next initial ones; false when nothing
  // was dropped or no line is left (nothing to solve again).
  bool drop_outliers(const SolveResult& result);
  bool enough_picks() const { return num_picks_ >= min_marks_; }

  // Why the solved lines `own` names are not a lane a car can drive at `speed_mps`
  // (lane_support.hpp); none when they are. Widths are judged loosely while the height
  // is not settled (mount_refinement.hpp).
  SupportProblem lane_support_problem(const SolveResult& r, const OwnLane& own, double speed_mps,
                                      const Attitude& mount,
                                      bool height_settled = true) const;
  // Whether a line runs inside the lane `own` names (lane_support.hpp's
  // kMinInsideLineDashes): the lane is then two, seen from a height taken too low, or a
  // lane with a seam and a vehicle's edges in it. Not a verdict of its own: a search
  // prefers a lane without one (lane_estimator.hpp).
  bool line_inside_lane(const OwnLane& own) const;
  // Whether one of the lines `own` names was found along its length in the picture
  // (line_in_picture.hpp) rather than from the marks the row filter kept: the weaker
  // evidence, which a search takes only when no pose gives a lane without it.
  bool line_from_picture(const OwnLane& own) const;
  // The picks of the lines found from the row filter's marks, not from the picture: what
  // a search that finds no lane compares its poses by (a line from the picture is looked
  // for beside any line, and adds its hits at any pose).
  int picks_from_marks() const;
  // Why solved line j, on its own, is not a line to report (lane_support.hpp): its marks
  // cover too little of the searched road, or it was placed only as a parallel of the
  // others; beside a supported lane (beside_a_lane), a single dash a lane's width from the
  // nearest line will do, as it does for one of the own lane's lines. None when it is a
  // line to report. The own lane's lines are judged by lane_support_problem; this judges
  // the lines beyond them. Not the paint-width checks: a line beyond the own lane is seen
  // only from farther off, where blur flattens the narrowing with distance they test
  // (a rendered road's leftmost line, 5.7 m out, failed them).
  SupportProblem line_problem(const SolveResult& r, int j, bool beside_a_lane) const;

  // The current problem, for the track stage and for overlays and diagnostics.
  const DetectionResult& detection() const { return *detection_; }
  std::span<const Pick> picks() const { return {picks_.data(), static_cast<std::size_t>(num_picks_)}; }
  std::span<const double> residual_px() const { return {residual_px_.data(), static_cast<std::size_t>(num_picks_)}; }
  int num_lines() const { return num_lines_; }
  // Per solver line: the tracker's prior it continues (-1: none).
  std::span<const int> prior_index() const { return {prior_index_.data(), static_cast<std::size_t>(num_lines_)}; }
  void clear() { num_picks_ = 0; }
  // Appends `more` to the problem's picks, as far as there is room; returns how many were
  // appended. remove_last_picks(n) takes the last n appended out again.
  int add_picks(std::span<const Pick> more);
  void remove_last_picks(int n) { num_picks_ = std::max(0, num_picks_ - n); }

 private:
  SolveRequest request(const CameraPose& initial, const std::optional<Gx1Angles>& gyro) const;
  void measure_residuals(const SolveResult& r);
  SupportProblem line_support_problem(const SolveResult& r, int left, int right, double lane_width_mm) const;
  LaneClutter own_lane_clutter(const OwnLane& own, InsidePieces* line_inside = nullptr, double faint_share = 0.0) const;
  // Whether both of `own`'s lines continue a tracked lane's (the tracker's priors).
  bool continues_track(const OwnLane& own) const;
  // Whether any line of the problem continues a tracked line.
  bool continues_a_track() const;
  // Solved line j's support as a full line: marks over enough of the searched road
  // (`support`, its line_support) and not placed only as a parallel of the others, which
  // is at most a dash's support whatever the number of its marks.
  SupportProblem full_support_problem(const LineSupport& support, int j) const;
  // Whether solved line j (`support`, its line_support) has a dash's support a lane's
  // width `lane_width_mm` from a line (check_dash_support), counting its picks that fit
  // and the marks detection grouped with it that handed on no pick (the blobs of a paint
  // line, a dash's rounded ends; beyond the per-line pick cap, more of its bars). Picks
  // are what says where the line lies; what was seen of it is all its marks, and
  // detection took the dash by them (GroupingParams::min_dash_marks). Counted by picks
  // alone, a far dash of five marks, one an end, was found and never reported.
  bool has_dash_support(const LineSupport& support, int j, double lane_width_mm) const;
  // Whether the marks of detection line `line` narrow with distance as one width does.
  SupportProblem paint_problem(int line) const;

  const LaneEstimatorOptions& options_;
  int min_marks_;
  LaneSolver solver_;
  const DetectionResult* detection_ = nullptr;
  // The picks and initial lines of the current solve (detection's, minus outliers).
  std::vector<Pick> picks_;
  int num_picks_ = 0;
  int num_lines_ = 0;
  std::array<RoadLine, kMaxLaneLines> initial_lines_{};
  std::array<int, kMaxLaneLines> prior_index_{};     // per solver line: detection's prior_index
  std::array<int, kMaxLaneLines> detection_line_{};  // per solver line: its line in detection()
  std::vector<double> residual_px_;                  // per pick, of the last solve
  mutable std::vector<double> scratch_;  // a median's values: the residuals', a line's paint widths'
  SolverPriors solve_priors_;  // of the last solve
  std::optional<Prior> previous_roll_;
};

}  // namespace ccdlane
