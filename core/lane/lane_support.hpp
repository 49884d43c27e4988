// Whether a solved lane has the support a real lane gives (no lane may be declared in
// noise): each own line's marks over a stretch of road inside the searched range, and a
// solve that agrees with its priors (the gyro's pitch and roll, a configured lane width).
#pragma once

#include <cstddef>
#include <optional>
#include <span>

#include "core/detection/detection_config.hpp"
#include "core/detection/lane_marks.hpp"
#include "core/detection/line_grouper.hpp"
#include "core/geometry/types.hpp"
#include "core/lane/lane_metrics.hpp"
#include "core/lane/support_problem.hpp"
#include "core/solver/lane_solver.hpp"
#include "core/solver/solver_options.hpp"

namespace ccdlane {

// A lane line's marks must cover this much road (mm, nearest to farthest) or, when the
// searched range is short, half of it. A real line does: solid over the whole range,
// dashed (3 m dashes, 9 m gaps) over several dashes; the shortest in the test pictures
// and drives covers 12.7 m. Chance alignments of blobs and bars in noise cover metres.
constexpr double kMinLineSpanMm = 8000.0;
// Marks solved this much nearer than min_range_mm or farther than max_range_mm (as a
// factor) lie where detection never looked: the pose that put them there is wrong.
constexpr double kRangeSlack = 1.5;
// Paint of one width on the road looks narrower with distance: its width in pixels goes
// as distance^-1. Across a line's marks, log(width px) against log(distance) must slope
// within kPaintWidthSlopeTolerance of -1 (blur and sampling flatten it at far range: the
// test pictures and drives give -1.02 .. -0.38); a bar of constant pixel width, which
// noise makes, slopes about 0.
constexpr double kPaintWidthSlope = -1.0;
constexpr double kPaintWidthSlopeTolerance = 0.75;
// A solve farther than this many of a prior's sigmas from it did not find what the
// prior describes (chi-square, 1 degree of freedom: p = 6e-5 for a real lane).
constexpr double kPriorAgreementSigmas = 4.0;
// How far off a configured height may be (a fraction): a user knows roughly where the
// camera is mounted. Until the height is settled, lane widths within this of the prior's
// mean agree with it.
constexpr double kUnsettledHeightError = 0.35;

// The lane a vehicle is in runs within this of its heading (a lane change at motorway
// speed takes a few degrees; the test drives reach 3.4). Lines that cross the vehicle's
// path more steeply are another road's, or noise.
constexpr double kMaxLaneHeadingDeg = 10.0;

// Pitch and roll without a prior (no gyro) stay within this of the mounting: a body
// pitches and rolls a few degrees when braking and cornering. A solve that tilts the
// camera farther has fitted lines to something else.
constexpr double kMaxBodyMotionDeg = 5.0;

// The vehicle's motion the lane implies, at the speed driven (the vehicle's input, else
// [vehicle] speed_kmh), must be a car's on a road:
// * Lateral speed v sin(heading): lane changes reach 0.6-1.5 m/s at their peak (the
//   synthetic ones 1.4 m/s), ISO 17361 tests departures up to 1 m/s; faster than this,
//   the vehicle would cross a lane in under 2 s.
constexpr double kMaxLateralSpeedMps = 2.0;
// * Lateral acceleration v^2 * curvature: roads are designed for about 2 m/s^2 at
//   their design speed (superelevation plus side friction, 0.2 g); this allows driving
//   40 % above it. A bend sharper than this at the speed driven is not being followed.
constexpr double kMaxLateralAccelerationMps2 = 4.0;

// Inside the own lane, between its lines, lies asphalt or concrete: an arrow (5 m) and a
// word (2.5 m letters) take a few metres of its length, where near rows give them as
// many marks as the lines have. So the clutter is measured in road length, in bins of
// kClutterBinMm of distance ahead: bins with marks inside the lane against bins with
// marks of its lines. Inside marks along more than half the length the lines are seen
// make the "lane" a field of bars (noise fills 6-10 bins of 2 m, the rendered arrows and
// words of tests/core/lane at most 6 while the lines fill 9-17). A real road's interior
// may be marked along as much of it (tar patches, seams and slab edges on concrete: the
// Udacity drives reach 12 bins of 18) but sparsely: a line gives a mark on nearly every
// row it crosses, a patch's edge a few. So a field of bars also holds as many marks as
// the lines: the noise "lanes" that reach this check (16 in 10,000 frames) hold 0.65 to
// 9 inside marks per line mark, the drives' lanes 0.2 to 0.5 where their lines are seen
// whole.
constexpr double kClutterBinMm = 2000.0;
constexpr double kMaxClutterPerLineLength = 0.5;
constexpr double kMaxClutterMarksPerLineMark = 0.5;
// What stands in the lane or is drawn on it as one thing (a vehicle ahead, whose upright
// edges and trim project onto the lane's far half as bars; an arrow's shaft) runs on as
// one bar from scan row to scan row; a field of bars does not line up. Marks inside the
// lane that run on over this many consecutive scan rows are not clutter (noise's bars
// seldom overlap from row to row four times running: the 10,000 noise frames still give
// no lane). The first kMaxClutterMarks inside marks are looked at so; any beyond count
// as clutter.
constexpr int kMinStandingRows = 4;
constexpr int kMaxClutterMarks = 1024;
// A field of bars makes its chance lines of the same bars it fills the lane with: the
// noise lanes that reach this check hold inside marks about as strong as their lines'
// (median contrast). A lane in a noisy picture holds the noise too, as bars far fainter
// than its paint (segB with pixel noise of sigma 6: the inside marks' median a ninth of
// the lines'), and was refused frame after frame. Not on a search: some noise lanes
// (bright bars, whose lines are a few strong bars in a field of weak ones) are like that
// too, and only their clutter refused them. A lane whose two lines continue a tracked
// lane's was found supported before; there, inside marks fainter than this share of its
// lines' median contrast are not clutter (docs/real-roads.md "Clutter inside the lane").
constexpr double kTrackedFaintClutterShare = 0.25;
// A lane has no lane line inside it. Two lanes look like one of a lane's width when the
// height the picture is seen from is taken half as high as it is (the same picture shows
// a lane of width W from height H and one of 2W from 2H, and a search tries heights a
// third apart): a lane bounded by lines two lanes apart, with the line between them inside
// it (detection keeps lines GroupingParams::min_separation_mm apart, which the lane's
// lines are not at that height). A search therefore prefers a lane without a line inside
// (lane_estimator.hpp); it is not a verdict on its own, since a real lane may hold what
// looks like one (a vehicle ahead, whose upright edges run on as bars; a seam along the
// lane with specks of concrete on it).
// What a line inside is: a dash runs on from scan row to scan row (over
// kMinInsideDashRows at least: far off, a 3 m dash spans two or three), a dashed line is
// such runs at one offset from the lane's lines, separated by its gaps; a
// row of raised markers is dots at one offset, often along a joint. Within a band
// kInsideLineBandMm wide (paint 10-15 cm, the lines as detection fitted them at a pose a
// little off; a vehicle's upright edge drifts across the band) and at least
// kInsideLineFromSide of the lane's width from either line (beside a line lie its shadow,
// a second stripe, its markers' offset from it), they make a line when they are
// kMinInsideLineDashes separate runs of kClutterBinMm bins, or kMinInsideLinePieces runs
// and bins with a dot (as many dots as detection takes as a row of them beside the road's
// lines: GroupingParams::min_parallel_dots), or GroupingParams::min_joint_dots of them
// along a joint seen in kMinInsideJointBins bins.
constexpr double kInsideLineBandMm = 250.0;
constexpr double kInsideLineFromSide = 0.25;
constexpr int kMinInsideLineDashes = 2;
constexpr int kMinInsideLinePieces = GroupingParams{}.min_parallel_dots;
constexpr int kMinInsideJointBins = 3;
constexpr int kMinInsideDashRows = 2;

// What the marks of one solved line cover. One mark alone does not make a line long: a
// bar of noise far beyond a short run of bars lies on the line through them wherever it
// is, so an end mark farther than this from every other mark is not counted (the gaps
// of dashed lines are 9 m in the US, 12 m on German motorways).
constexpr double kIsolatedMarkGapMm = 15000.0;
struct LineSupport {
  int marks = 0;
  double near_mm = 0.0, far_mm = 0.0;  // nearest and farthest solved mark (road x), isolated ends left out
};

// Line `line`'s picks among `picks`, with their solved mark positions `points_mm` (one per
// pick, as SolveResult::points_mm).
LineSupport line_support(std::span<const Pick> picks, std::span<const Vec2> points_mm, int line);


SupportProblem check_line_support(const LineSupport& line, const DetectionConfig& detection);

// Whether a line that fails check_line_support still has the support of one dash, as
// detection accepts it beside the road's other lines: grouping.min_dash_marks marks over
// grouping.min_dash_span_mm, inside the searched range, forming a lane of a lane's width
// with the fully supported line (noise bars beside a line formed a 2.25 m "lane").
bool check_dash_support(const LineSupport& line, const DetectionConfig& detection, const GroupingParams& grouping,
                        double lane_width_mm);

// A lane with one side a single dash must be this wide: narrower at the top than
// lane_metrics' kMinLaneWidthMm..kMaxLaneWidthMm, which admits any lane two full lines
// make; a dash has too little support of its own to admit the unusual ones (merges).
constexpr double kMinDashLaneWidthMm = kMinLaneWidthMm;
constexpr double kMaxDashLaneWidthMm = 5000.0;

// The slope of log(width px) against log(road distance) over a detection line's marks of
// its majority kind (DetectedLine::dots: a line is judged by that kind, as its picks are;
// dots of one size narrow as paint does): paint_width_slope for paint, line_grouper.hpp's
// width_distance_slope for dots.
SupportProblem check_paint_width(double slope);

// The slope for a line's paint marks (not dots): Theil-Sen's, the median of the slopes
// between every two marks (at least kMinPaintSlopeLogSpan apart in log distance), so that
// it says what most marks say. A least-squares slope follows a few odd marks at the
// line's ends: a noise bar of one pixel width with one thin mark of something else 20 m
// beyond it sloped -0.6, as paint does, where its other 41 marks said 0. A dot's rows are
// chords of it, whose widths spread by nature; over dots the least-squares slope averages
// them, so dots keep it. NaN with fewer than 3 marks or all at one distance; at most
// kMaxPaintSlopeMarks marks are taken (every k-th of a longer line: the pairs are its
// square, on the stack).
inline constexpr std::size_t kMaxPaintSlopeMarks = 64;
inline constexpr double kMinPaintSlopeLogSpan = 0.05;
double paint_width_slope(std::span<const MarkCandidate> marks, int detection_line);

// One line's paint has one width on the road: log(width px x distance) is the same for
// most of its marks but for edge noise and blur. Most, not all: a worn dash reads half as
// wide as the paint beyond it, colour bleeds into a yellow line's sides on pale concrete,
// blur widens the far marks (the drives: a third of a dashed line's marks at 0.42 of the
// others' width; far marks up to 1.4 times as wide as near ones). So the spread is the
// median absolute deviation from the median, which those leave small. Marks of bars of
// several widths spread as far as detection's width gate lets them: for widths uniform
// over [min, max] the median deviation is ln(max / min) / 4 (0.27 for 100-300 mm), and a
// line spreading that much is a mix of bars, not one paint. Over the line's paint marks
// only, at most scratch.size() of them (scratch holds their values): a dot's rows are
// chords of it, whose widths spread by nature (lane_fit does not ask it of a line of dots).
double paint_width_spread(std::span<const MarkCandidate> marks, int detection_line,
                          std::span<double> scratch);  // NaN with < 3 marks
SupportProblem check_paint_width_spread(double spread, const DetectionConfig& detection);

// Pieces of a line inside a lane (bars running on, dots, joints) at one offset from its lines.
struct InsideMark {  // trivial: a clutter check that does not look for a line leaves its buffer untouched
  double offset, X;  // mm: from the lane's left line (detection fit), ahead
  enum Kind : std::uint8_t { dash, dot, joint } kind;
};
struct InsidePieces {
  int dashes = 0;  // separate runs of bars along the road
  int dots = 0;    // kClutterBinMm bins holding a dot
  int joints = 0;  // bins holding a piece of a joint between slabs
};

// Marks no line took lying inside the lane bounded by detection lines `left` and `right`
// (at least `margin_mm` from each), against the marks the two lines took: how many bins
// of kClutterBinMm of road distance hold each (distances beyond 64 bins share the last),
// and how many marks.
struct LaneClutter {
  int inside_bins = 0;
  int line_bins = 0;
  int inside_marks = 0;
  int line_marks = 0;
  int standing_marks = 0;  // inside, but running on as one bar (not counted above)
  int faint_marks = 0;     // inside, but fainter than `faint_share` of the lines' (not counted above)
};
// With `line_inside`, also the most pieces of one line inside the lane there (a search's
// question, kMinInsideLineDashes; a tracking frame's clutter check does without). Inside
// marks fainter than `faint_share` times the median contrast of the two lines' marks are
// counted apart (faint_marks); 0 counts every one.
LaneClutter lane_clutter(std::span<const MarkCandidate> marks, const RoadLine& left, int left_line,
                         const RoadLine& right, int right_line, double margin_mm, InsidePieces* line_inside = nullptr,
                         double faint_share = 0.0);
SupportProblem check_clutter(const LaneClutter& clutter);
// Whether pieces at one offset inside a lane make a line (kMinInsideLineDashes).
bool is_line_inside(const InsidePieces& pieces);

// The lateral speed and acceleration of a vehicle at `speed_mps` with this heading
// (degrees) in a lane of this curvature (1/m).
SupportProblem check_motion(double speed_mps, double heading_deg, double curvature_per_m);

// How far a tracked frame's own line may lie from the line it was on the frame before
// (the one it continues, or the own line on its side when it was found anew), beyond what
// the vehicle moves sideways in between (kMaxLateralSpeedMps): the scatter of a line's
// offset at the car from frame to frame. On the Udacity drives at every mount the most
// was 280 mm (segB's dashed line on concrete, when its nearest dash left the picture and
// its far dashes placed it; segA's 250 mm).
constexpr double kOwnLineStepSlackMm = 400.0;
// Whether an own line at `y0_mm` is a jump from where it was tracked, `tracked_y0_mm`,
// `dt_s` before: farther from it than the vehicle moves sideways in that time plus the
// slack, and nearer than half a lane (`lane_width_mm`), where the line beside it would be
// after a lane change. Such a line is something else taken for the own line (a bend's
// tree shadows on concrete where a car beside hid the dashes: 720 mm out at the car, the
// yaw 3.5 degrees off to match): check_motion's implausible_motion, as the lane would
// have moved sideways faster than a car does.
bool own_line_jumped(double y0_mm, double tracked_y0_mm, double dt_s, double lane_width_mm);

// How fast a vehicle turns against its lane (a swerve; at 90 km/h 4 m/s^2 of lateral
// acceleration is 9 degrees a second), and how far a tracked frame's solved yaw scatters
// from the frame before's besides: on the Udacity drives at every mount at most 0.79
// degrees (segB's bridge, where a dashed line's near dash comes and goes).
constexpr double kMaxYawRateDegPerS = 20.0;
constexpr double kYawStepSlackDeg = 1.0;
// Whether a tracked frame's yaw (degrees) turned from the frame before's, `dt_s` before,
// faster than a vehicle turns plus the slack: a lane fitted to something else, the yaw
// turned to match it (the rendered bends with cars beside: 1.9-3.5 degrees in a frame).
bool yaw_jumped(double psi_deg, double tracked_psi_deg, double dt_s);

// A lane's own lines at the car (`left_mm` > 0 > `right_mm`, the solve's y0) and the
// camera height they were solved at.
struct OwnLanePlace {
  double left_mm = 0.0, right_mm = 0.0, H_mm = 0.0;
  double width_mm() const { return left_mm - right_mm; }
};
// Two lanes a search found in one picture from different heights are alike but for the
// scale only when they are one lane: the picture fixes every road distance only in
// proportion to the height. Taken to one height, a lane whose line lies on one of the
// other's and whose other line lies inside the other (kInsideLineFromSide of its width
// from both of its lines) shows the other to be two lanes taken for one: seen from a
// height too low, the own line and the next lane's beyond make a lane's width (TuSimple
// stills from a mount a quarter too low: 0.75 m, where the lanes say 1.65).
// kSharedLineShare of the wide lane's width is how near a line lies on another: the
// solves' poses differ by tenths of a degree, and a line's place with them.
constexpr double kSharedLineShare = 0.1;
// Whether `wide` is two lanes, as `narrow` shows.
bool spans_two_lanes(const OwnLanePlace& wide, const OwnLanePlace& narrow);

// Without a measured speed, the slowest a lane's bend is taken to be driven at.
constexpr double kMinUnmeasuredSpeedMps = 10.0;
// The speed check_motion judges a lane of this curvature (1/m) at: the vehicle's measured
// speed; without one, the configured speed ([vehicle] speed_kmh) unless the bend is too
// sharp for it, then the speed a car takes the bend at (kMaxLateralAccelerationMps2), not
// below kMinUnmeasuredSpeedMps. A drive replayed from a video has no speed: at the
// configured 72 km/h every bend sharper than 100 m radius was refused, which a car takes
// at 36 km/h on a country road or in a town. So without a speed the lateral acceleration
// bounds the bend at 25 m radius.
double judged_speed_mps(std::optional<double> measured_mps, double configured_mps, double curvature_per_m);

// The solved pose and own lane width against the priors of the solve (angles in degrees,
// lengths in mm; a prior left empty is not checked).
SupportProblem check_priors(const SolverPriors& priors, const CameraPose& pose, double lane_width_mm);

// The solved pitch and roll that have no prior in `priors` against the mounting's.
SupportProblem check_body_motion(const SolverPriors& priors, const Attitude& solved, const Attitude& mount);

// The vehicle's heading relative to the lane (LaneMetrics::heading_deg).
SupportProblem check_heading(double heading_deg);

}  // namespace ccdlane
