// The per-frame pipeline shared by `ccdlane replay`, `ccdlane calibrate mount` and the
// daemon: a short sequence of stages, each in its own file with a typed result
// (docs/architecture.md "One frame"): detect lane marks (core/detection), fit them
// (lane_fit.hpp: solve with gyro roll/pitch as priors, drop outliers), track the lines
// (tracked_lines.hpp: ids, order, lane metrics), check the lane's support
// (lane_fit.hpp), and run the lane departure warning (core/ldw/ldw_monitor.hpp), into a
// LaneEstimate every field of which is set in one place (report()); then refine the
// mount from that estimate for the frames after it (mount_refinement.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/detection/lane_detector.hpp"
#include "core/detection/vanishing_lines.hpp"
#include "core/detection/vanishing_point.hpp"
#include "core/geometry/gx1_attitude.hpp"
#include "core/lane/frame_inputs.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_estimator_options.hpp"
#include "core/lane/lane_fit.hpp"
#include "core/lane/lane_support.hpp"
#include "core/lane/lane_tracker.hpp"
#include "core/lane/mount_refinement.hpp"
#include "core/lane/tracked_lines.hpp"
#include "core/ldw/ldw_monitor.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane {

class LaneEstimator {
 public:
  // Sizes every workspace (detector, solver, pick buffers) from the options. May
  // allocate and throw (std::bad_alloc); estimate() then never does either.
  explicit LaneEstimator(const LaneEstimatorOptions& options);

  // One frame (app/frame_inputs.hpp builds them): its image must be camera.Nu x
  // camera.Nv, or empty for a frame that could not be read (ok = false, no_frame; the
  // lane filter coasts). The result stays valid until the next call. latency_us is left
  // at 0: the caller, who owns the clock, measures it. Frames must come in time order
  // (t_ns drives the lane filter).
  const LaneEstimate& estimate(const FrameInputs& in);

  // The same, for callers that have only these (tests, tools): frame and source_frame
  // are `frame`, the attitude recorded.
  const LaneEstimate& estimate(const ImageView& image, std::uint64_t frame, std::int64_t t_ns,
                               const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle = {});
  const LaneEstimate& no_frame(std::uint64_t frame, std::int64_t t_ns, const VehicleInputs& vehicle = {});

  // Forgets the previous frames (their pose and lines, the lane departure warning's track
  // and state, and the start's mount acquisition; not the online refinement's correction).
  void reset();

  // What the last estimate() was made of, for overlays and diagnostics.
  const DetectionResult& detection() const { return fit_.detection(); }
  std::span<const Pick> solved_picks() const { return fit_.picks(); }
  const SolveResult* solution() const { return solution_; }  // null when no solve ran
  const CameraPose& detection_pose() const { return detection_pose_; }
  // The vanishing point the last estimate() looked for (searching), null when it went on
  // from the previous frame.
  const VanishingPoint* vanishing_point() const { return vanishing_point_; }
  // The mount the estimator goes by: the configured one (with the online correction), or
  // what the road showed when that was more than MountRefinement::kMountTrustDeg off.
  const Attitude& mount() const { return mount_.mount(); }
  // The online mount refinement after the last estimate(): what the daemon reports and
  // keeps in its state file (status off when not configured).
  const MountRefinementResult& mount_refinement() const { return mount_.result(); }
  // A track that makes no lane for this many frames in a row is searched afresh: a second
  // at 25 frames/s, longer than a dash gap or a truck hides both lines.
  static constexpr int kMaxTrackedFramesWithoutLane = 25;
  // Without a gyro, one lane holds the roll loosely, and a bend takes up what a roll error
  // makes of the lines: a car standing still (TuSimple still 50 held) had its tracked
  // solves walk the roll from -1.8 to -5 degrees onto a bend of 270 m, frame by frame, on
  // a picture that did not change. A car's body rolls by tenths of a degree between
  // frames; a tracked frame's roll is held by the frame before's as a random walk of this
  // spread (0.5 degrees between frames 40 ms apart), besides the configured prior.
  static constexpr double kRollWalkDegPerSqrtS = 2.5;
  // A search without a previous frame also starts from the mount pitched by these steps,
  // out to this bound (detection loses lines from a pose a degree or two off; the solve
  // from what it finds, and the look again from the solved pose, bring it back). The
  // bound: a picture's own tilt nobody wrote down (a TuSimple still's 7 degrees) and a
  // user's 5, for when the vanishing point is not found (TuSimple's "pitch -5", 12 off:
  // own lines 70.6 -> 80.0 % with 9 -> 12 here).
  static constexpr double kSearchPitchStepDeg = 3.0;
  static constexpr double kSearchPitchDeg = 12.0;
  // And the picture's vanishing point's pose pitched this far either way: half the
  // pitch error a search pose's detection allows (kSearchPitchErrorDeg). The point's
  // pitch is within a degree of the lane's solve on 80 % of the TuSimple stills and
  // within 1.5 on 90 % (at the nominal mount; 0.7 and 3.3 from a mount pitched 5
  // degrees down), but each pose's detection groups other bars, and the nearest of the
  // mount's steps may lie 1.5 degrees off (docs/real-roads.md).
  static constexpr double kVanishingPitchStepDeg = kSearchPitchErrorDeg / 2.0;
  // And, while the mount's height is not settled, at the configured height times and
  // over this, and its square (kSearchHeights in all). A configured height may be a third
  // off (kUnsettledHeightError), and what a picture shows of it more: TuSimple's file
  // says 1.3 m for a camera 1.7 m up, and with a user's quarter more error that is 0.57
  // of the truth (own lines 70.0 -> 81.7 % in its "height x0.75" row with the squares).
  static constexpr double kSearchHeightStep = 1.3;
  static constexpr int kSearchHeights = 5;
  // The scale by which a cold start's first solve, at pose_H_mm, says the height is off:
  // the lane-width prior's mean over the width of the lane it found. Taken when the height
  // it gives lies among the heights the search itself tries about the mount's
  // (kSearchHeightStep to the power of -2 to 2 times mount_H_mm), wherever the pose's own
  // height was: a solve from the search's highest step whose lane is 1.38 times a lane's
  // width says 1.23 times the mount's height, a height the search would try; one whose
  // lane is 0.67 times says 2.5 times, one it would not. 1 otherwise.
  static double height_scale_for(double pose_H_mm, double mount_H_mm, double own_width_mm, double prior_width_mm);
  // What a search's supported lane says of the height: a lane of a lane's width at the
  // height it was looked from; one that needed another height (of another width and not
  // looked at again, or looked at again from the height its width said and a lane's
  // width there), the weaker evidence; or neither (looked at again and still of another
  // width: not a lane at any height the search took).
  enum class LaneHeight : std::uint8_t { as_looked_from, another, neither };
  static LaneHeight lane_height(bool rescaled, bool width_agrees);
  // Where the lines of bars may cross: 15 degrees either side of the mount in pitch and
  // yaw (the edge vote, easier fooled, looks within 10). A camera whose mount a user
  // knows to 5 degrees on a car that pitches a few, with a picture whose own tilt (a
  // TuSimple still's 7 degrees) nobody wrote down.
  static constexpr VanishingPointSearch kLineSearch{15.0, 15.0};
  static_assert(kLineSearch.max_yaw_error_deg == MountRefinement::kMountReachDeg &&
                    kLineSearch.max_pitch_error_deg == MountRefinement::kMountReachDeg,
                "a solve is the camera's as far from the mount as the search looks");
  const ldw::LdwMonitor& ldw_monitor() const { return ldw_; }
  // Why the last estimate()'s lines were not taken for a lane (reason no_lane) although
  // a line lay on each side the right distance apart; none otherwise.
  SupportProblem support_problem() const { return support_; }

 private:
  // The stages, in the order estimate() runs them.
  const SolveResult* detect_and_fit(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                    const VehicleInputs& vehicle);
  // The solve `r` (the fit's last, as track() takes it) again with the raised markers in
  // the own lines' gaps near the car as picks of their lines (gap_markers.hpp), when there
  // are any and that converges; else `r`, or (the solver's storage having held the try)
  // the same picks solved again from its pose.
  const SolveResult* with_gap_markers(const SolveResult& r, const std::optional<Gx1Angles>& gyro);
  static constexpr int kMaxGapMarkers = 16;
  // A detect and fit from detection_pose_: the solve when it converged (rank deficient
  // or not), and why not otherwise; nothing is committed.
  struct Attempt {
    const SolveResult* solve = nullptr;
    EstimateFailure why = EstimateFailure::none;
    bool rescaled = false;  // the first solve's lane width moved the height (height_scale)
    // A cold attempt's first solve had two lines or more bending sharper than
    // kTangentRadiusMm: looked at again along that bend (attempt's along_bend), its far
    // marks may be seen where the straight road's point refused them.
    bool bent = false;
  };
  // `along_bend`: a cold attempt's look again judges bars against the road's tangent when
  // its first solve bent sharply (search() asks it once it found no lane). `afresh`: cold
  // although a previous frame's lines are tracked (look_afresh).
  Attempt attempt(const ImageView& image, const std::optional<Gx1Angles>& gyro, bool along_bend = false,
                  bool afresh = false);
  // A tracked frame's attempt that made no lane, looked at once more from its pose
  // without the previous frame's lines, then from the pose the last search found its
  // lane from; the tracked attempt again unless one of them is a lane.
  Attempt look_afresh(const ImageView& image, const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle);
  // A search's lane, whose look again was planned from a first solve at least
  // kLookBeyondAgainDeg away from `lane`'s pose, looked at once more from that pose for
  // the lines beyond it. The new solve when it has more lines, is the same lane and still
  // a lane; `lane` itself when no look was needed; null when the look did not take (the
  // fit's buffers then hold it, not `lane`'s).
  const SolveResult* look_beyond_again(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                       const VehicleInputs& vehicle, const SolveResult& lane);
  // `lane`, the attempt from `from` whose solve is a search's lane, after
  // look_beyond_again: its solve or the look's.
  Attempt with_lines_beyond_again(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                                  const VehicleInputs& vehicle, const CameraPose& from, Attempt lane);
  static constexpr double kLookBeyondAgainDeg = 1.0;
  // The same lane's width from two solves differs by less than this (its lines a mark's
  // width or two apart); another line taken for one of its own moves it by a metre.
  static constexpr double kSameLaneWidthMm = 300.0;
  static constexpr int kMaxSearchAttitudes = 12;
  static constexpr int kMaxSearchPoses = kSearchHeights * kMaxSearchAttitudes;
  // Yaw and pitch from the road's vanishing point in the picture (roll and the rest are
  // base's); empty when none is found.
  std::optional<Attitude> attitude_from_picture(const ImageView& image, const CameraPose& base);
  // The poses a search starts from: count of them, height by height, per_height at each.
  struct SearchPoses {
    int count = 0;
    int per_height = 0;
  };
  SearchPoses search_poses(const ImageView& image, const std::optional<Gx1Angles>& gyro,
                           std::array<CameraPose, kMaxSearchPoses>& poses);
  Attempt search(const ImageView& image, const std::optional<Gx1Angles>& gyro, const VehicleInputs& vehicle);
  // Whether a solve is a supported lane, and whether a line runs inside it.
  // What a search's pose gives: no lane, a lane, or one of the weaker kinds search() takes
  // only when no pose gives a lane.
  enum class Found : std::uint8_t { nothing, lane, lane_with_a_line_inside, lane_with_a_line_from_the_picture };
  Found supported(const SolveResult& r, const VehicleInputs& vehicle) const;
  // Whether r's yaw turned from the last tracked frame's faster than a vehicle turns
  // (yaw_jumped), or an own line of r jumped from the `tracked` line it continues (the
  // frame before's), or, found anew, from the own line the tracked lines had on its side
  // (own_line_jumped; lane_support.hpp): a tracked frame's lane is then not supported.
  bool jumped_from_track(const SolveResult& r, const OwnLane& own, std::span<const RoadLine> tracked) const;
  // The speed the lane's motion is judged at (lane_support.hpp, judged_speed_mps).
  double motion_speed_mps(const VehicleInputs& vehicle, const OwnLane& own) const;
  const SolveResult& solve(const CameraPose& initial, const std::optional<Gx1Angles>& gyro);
  // By how much a cold start's first solve says the height is off, while the mount's
  // height is not settled: the lane-width prior's mean over the width of the lane it
  // found, when that is clearly not a lane's width; 1 otherwise.
  double height_scale(const SolveResult& r) const;
  // Whether the mount's height is still to be settled from the lanes' width (a lane-width
  // prior and not settled), and whether r's own lane is of the prior's width at r's
  // height (always, when the height is not to be settled or r has no own lane).
  bool height_unsettled() const;
  bool width_agrees_with_height(const SolveResult& r) const;
  // The solve's own lane's lines and height, and its width; none without a line on each
  // side.
  static std::optional<OwnLanePlace> own_lane_place(const SolveResult& r);
  static std::optional<double> own_lane_width(const SolveResult& r);
  void track(const SolveResult& r, const VehicleInputs& vehicle);
  void warn(const FrameInputs& in);
  void report(const FrameInputs& in);
  // Then mount_.refine(): the mount learns from the estimate, for the frames after it.

  const SolveResult* fail(EstimateFailure why);
  CameraPose guess_pose(const std::optional<Gx1Angles>& gyro) const;
  CameraPose nominal_pose() const;  // the configured position with the mount in use
  void reset_lines();
  // The mount's height changed: the tracked lines, measured at the last pose's height,
  // are scaled to the new one.
  void rescale_lines();
  void miss();

  LaneEstimatorOptions config_;  // nominal_pose.attitude: the configured mount (mount_ has the one in use)
  bool roll_needs_gyro_;         // observability.hpp: a frame without a gyro reading is roll_unobservable
  LaneDetector detector_;
  LaneFit fit_;
  LaneTracker tracker_;
  ldw::LdwMonitor ldw_;
  MountRefinement mount_;
  CameraPose last_pose_;
  bool have_last_ = false;
  bool track_had_lane_ = false;  // the lines tracked made a lane (ok) since they were found
  bool rescaled_ = false;        // the mount acquisition changed the height this frame
  bool rescaled_before_ = false;  // and on the frame before this one
  int misses_ = 0;               // frames in a row without an estimate
  std::int64_t frame_t_ns_ = 0;  // this frame's time
  std::int64_t tracked_t_ns_ = 0;  // the time of the frame whose lines the tracker holds
  // Tracked frames in a row without a lane (ok): a track of lines that makes no lane for
  // kMaxTrackedFramesWithoutLane frames is searched afresh, as it may be a wrong start's
  // (a first frame's lane of the wrong lines, which each frame's priors keep finding).
  int without_lane_ = 0;

  // This frame's stage results, which report() turns into the estimate.
  CameraPose detection_pose_;
  EstimateFailure failure_ = EstimateFailure::none;  // of detect and fit
  const SolveResult* solution_ = nullptr;            // the last solve, null when none ran
  const SolveResult* lane_solve_ = nullptr;          // the solve the lines were taken from
  TrackedLines tracked_;
  SupportProblem support_ = SupportProblem::none;
  LaneEstimate estimate_;

  // The pose the last search found its lane from (a starting pose, before its solve):
  // where a lost lane is looked for once more before a search (look_afresh).
  CameraPose search_found_from_;
  bool have_search_pose_ = false;
  // The pose the last frame with a lane was detected from (the one before its solve):
  // where a tracked frame that loses its lane looks once more (look_afresh).
  CameraPose lane_found_from_;
  bool have_lane_pose_ = false;

  // The search without a previous frame (docs/real-roads.md).
  VanishingLineFinder line_finder_;
  VanishingPointFinder vp_finder_;
  const VanishingPoint* vanishing_point_ = nullptr;
  EstimatorState state_ = EstimatorState::searching;
};

}  // namespace ccdlane
