// The fit stage's own rules: a detection with too few picks is not taken, a detection's
// fixed slopes and curvatures start at 0, a solve that fits well drops nothing, and the
// lane-width prior holds for the own lane, not for a shoulder beside it.
#include "core/lane/lane_fit.hpp"

#include <cmath>
#include <initializer_list>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "app/config.hpp"

namespace ccdlane {
namespace {

// Two lines of `per_line` picks each, fitted by detection as given.
DetectionResult detection_of(std::vector<Pick>& picks, int per_line) {
  DetectionResult d;
  d.num_lines = 2;
  d.lines[0].fit = {1800.0, 0.01, 1e-6};
  d.lines[1].fit = {-1800.0, 0.01, 1e-6};
  d.lines[1].prior_index = 3;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < per_line; ++i) picks.push_back({j, 100.0 + 10.0 * i, 300.0 + i});
  d.picks = picks;
  return d;
}

TEST(LaneFit, TakesADetectionOnlyWithEnoughPicks) {
  LaneEstimatorOptions o;
  LaneFit fit(o);
  std::vector<Pick> few, enough;
  EXPECT_FALSE(fit.take(detection_of(few, o.detection.min_marks / 2 - 1)));
  const DetectionResult d = detection_of(enough, o.detection.min_marks);
  ASSERT_TRUE(fit.take(d));
  EXPECT_EQ(fit.num_lines(), 2);
  EXPECT_EQ(fit.picks().size(), enough.size());
  EXPECT_EQ(fit.prior_index()[1], 3);
  ASSERT_TRUE(fit.take(d, true));
  EXPECT_EQ(fit.prior_index()[1], -1) << "this frame's own lines continue no previous frame's";
  fit.clear();
  EXPECT_TRUE(fit.picks().empty());
}

TEST(LaneFit, AWellFittingSolveDropsNothing) {
  LaneEstimatorOptions o;
  LaneFit fit(o);
  std::vector<Pick> picks;
  ASSERT_TRUE(fit.take(detection_of(picks, o.detection.min_marks)));
  SolveResult r;
  r.rms_px = o.solver.pixel_sigma;  // within twice the pick noise
  EXPECT_FALSE(fit.drop_outliers(r));
}

// The reference camera without a gyro (roll held by a loose prior), looking 2 degrees
// up from 1.3 m: the truth the synthetic detections below are drawn at.
LaneEstimatorOptions options_without_gyro() {
  LaneEstimatorOptions o = default_config().estimator_options();
  o.priors.phi_deg = Prior{0.0, 1.0};
  return o;
}
CameraPose truth_pose(const LaneEstimatorOptions& o) {
  return CameraPose{{0.0, deg_to_rad(-2.0), 0.0}, 1300.0, o.nominal_pose.f_mm};
}

// A detection of straight lines at these offsets, each with noisy picks (sigma the
// solver's pixel_sigma) of its marks from `from_mm` to `to_mm` ahead every `step_mm`, as
// the truth pose's camera sees them; detection's fits 50 mm off the truth.
struct LineMarks {
  double y0_mm, from_mm, to_mm, step_mm;
};
DetectionResult detection_of_lines(const LaneEstimatorOptions& o, const CameraPose& truth,
                                   std::initializer_list<LineMarks> lines, std::mt19937_64& rng,
                                   std::vector<Pick>& picks) {
  const CameraModel camera(o.camera, truth);
  std::normal_distribution<double> noise(0.0, o.solver.pixel_sigma);
  picks.clear();
  DetectionResult d;
  for (const LineMarks& l : lines) {
    const int j = d.num_lines++;
    d.lines[j].fit = {l.y0_mm + 50.0, 0.0, 0.0};
    d.lines[j].marks = 0;
    for (double x = l.from_mm; x <= l.to_mm; x += l.step_mm) {
      const auto px = camera.pixel_from_point(Vec3(x, l.y0_mm, 0.0));
      if (!px) continue;
      picks.push_back({j, px->x() + noise(rng), px->y() + noise(rng)});
      ++d.lines[j].marks;
    }
    d.lines[j].num_picks = d.lines[j].marks;  // every mark a bar of paint, handed on
  }
  d.picks = picks;
  return d;
}

// No gyro: roll is free with a loose prior, and parallel straight lines hardly fix it (a
// roll is taken up by the lines' offsets): the lane-width prior does. A road's outermost
// lines are not always a whole number of lanes apart: a barrier's foot 2.4 m beyond the
// left line, 6.06 m from the right one, is "two lanes" of 3.66 m to a prior held between
// the outermost lines, and the solve rolled the camera 1.3 deg to widen them (on the
// drives, by a degree each time the barrier's line came and went). Held between the own
// lane's lines, the roll and the width are the truth's, to within what the picks' noise
// moves them: over independent draws, their mean within 4 standard errors of the truth.
TEST(LaneFit, TheLaneWidthPriorHoldsForTheOwnLaneBesideAShoulder) {
  LaneEstimatorOptions o = options_without_gyro();
  o.priors.lane_width_mm = Prior{3660.0, 300.0};
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(27);
  LaneFit fit(o);
  constexpr int kDraws = 16;
  double roll[kDraws], width[kDraws];
  std::vector<Pick> picks;
  for (int draw = 0; draw < kDraws; ++draw) {
    const DetectionResult d = detection_of_lines(
        o, truth, {{1830.0, 6000.0, 40000.0, 1700.0}, {-1830.0, 6000.0, 40000.0, 1700.0}, {4230.0, 6000.0, 40000.0, 1700.0}},
        rng, picks);
    ASSERT_EQ(picks.size(), 3u * 21u);
    ASSERT_TRUE(fit.take(d));
    const SolveResult& r = fit.solve(CameraPose{{}, truth.H_mm, truth.f_mm}, std::nullopt);
    ASSERT_TRUE(r.converged) << to_string(r.status);
    roll[draw] = rad_to_deg(r.pose.attitude.phi);
    width[draw] = r.lines[0].y0_mm - r.lines[1].y0_mm;
  }
  const auto expect_unbiased = [](const double* v, double truth_value, const char* what) {
    double mean = 0.0, var = 0.0;
    for (int i = 0; i < kDraws; ++i) mean += v[i] / kDraws;
    for (int i = 0; i < kDraws; ++i) var += (v[i] - mean) * (v[i] - mean) / (kDraws - 1);
    EXPECT_LT(std::abs(mean - truth_value), 4.0 * std::sqrt(var / kDraws)) << what << ": mean " << mean;
  };
  expect_unbiased(roll, 0.0, "roll, deg");
  expect_unbiased(width, 3660.0, "lane width, mm");
}

// The lines beyond the own lane are reported with the own lane's line rules: marks over
// 8 m of the searched road, or, beside a supported lane, a dash a lane's width from the
// nearest line (marks over a metre); a few marks over half a metre are neither.
TEST(LaneFit, ALineBeyondTheOwnLaneNeedsALinesSupportOrADashBesideALane) {
  const LaneEstimatorOptions o = options_without_gyro();
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(5);
  std::vector<Pick> picks;
  const DetectionResult d = detection_of_lines(o, truth,
                                               {{1830.0, 6000.0, 40000.0, 1700.0},
                                                {-1830.0, 6000.0, 40000.0, 1700.0},
                                                {5490.0, 12000.0, 30000.0, 1500.0},   // a line: 18 m
                                                {-5490.0, 14000.0, 15800.0, 300.0}},  // a dash: 1.8 m
                                               rng, picks);
  LaneFit fit(o);
  ASSERT_TRUE(fit.take(d));
  const SolveResult& r = fit.solve(CameraPose{{}, truth.H_mm, truth.f_mm}, std::nullopt);
  ASSERT_TRUE(r.converged) << to_string(r.status);
  EXPECT_EQ(fit.line_problem(r, 0, true), SupportProblem::none);
  EXPECT_EQ(fit.line_problem(r, 2, false), SupportProblem::none);
  EXPECT_EQ(fit.line_problem(r, 3, false), SupportProblem::too_few_marks);  // 7 marks
  EXPECT_EQ(fit.line_problem(r, 3, true), SupportProblem::none) << "a dash beside a lane";
  // Half a metre of marks is no dash.
  const DetectionResult spot = detection_of_lines(o, truth,
                                                  {{1830.0, 6000.0, 40000.0, 1700.0},
                                                   {-1830.0, 6000.0, 40000.0, 1700.0},
                                                   {-5490.0, 14000.0, 14500.0, 100.0}},
                                                  rng, picks);
  ASSERT_TRUE(fit.take(spot));
  const SolveResult& s = fit.solve(CameraPose{{}, truth.H_mm, truth.f_mm}, std::nullopt);
  ASSERT_TRUE(s.converged) << to_string(s.status);
  EXPECT_NE(fit.line_problem(s, 2, true), SupportProblem::none);
}

// A far dash as detection takes it beside the road's lines: five marks over a metre, one
// of them its rounded end, a blob that hands on no pick (LaneDetector::choose_picks). The
// dash's support counts what detection saw of it, its end too; four bars alone are too few.
TEST(LaneFit, ADashsEndCountsForItsSupportThoughItHandsOnNoPick) {
  const LaneEstimatorOptions o = options_without_gyro();
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(9);
  std::vector<Pick> picks;
  DetectionResult d = detection_of_lines(o, truth,
                                         {{1830.0, 6000.0, 40000.0, 1700.0},
                                          {-1830.0, 6000.0, 40000.0, 1700.0},
                                          {-5490.0, 20000.0, 21200.0, 400.0}},  // four bars over 1.2 m
                                         rng, picks);
  ASSERT_EQ(d.lines[2].num_picks, GroupingParams{}.min_dash_marks - 1);
  LaneFit fit(o);
  ASSERT_TRUE(fit.take(d));
  const SolveResult& r = fit.solve(CameraPose{{}, truth.H_mm, truth.f_mm}, std::nullopt);
  ASSERT_TRUE(r.converged) << to_string(r.status);
  EXPECT_EQ(fit.line_problem(r, 2, true), SupportProblem::too_few_marks) << "four bars";
  ++d.lines[2].marks;  // and the dash's end
  ASSERT_TRUE(fit.take(d));
  const SolveResult& s = fit.solve(CameraPose{{}, truth.H_mm, truth.f_mm}, std::nullopt);
  ASSERT_TRUE(s.converged) << to_string(s.status);
  EXPECT_EQ(fit.line_problem(s, 2, true), SupportProblem::none) << "four bars and the dash's end";
}

// Detection `d` solved from a level pose at the truth's height, its lines 0 (left) and 1
// (right) judged as the estimator judges an own lane.
SupportProblem solved_lane_support(const LaneEstimatorOptions& o, const CameraPose& truth, const DetectionResult& d) {
  LaneFit fit(o);
  EXPECT_TRUE(fit.take(d));
  const SolveResult& r = fit.solve(CameraPose{{}, truth.H_mm, truth.f_mm}, std::nullopt);
  EXPECT_TRUE(r.converged) << to_string(r.status);
  const OwnLane own{0, 1, r.lines[0].y0_mm - r.lines[1].y0_mm, 0.0, 0.0};
  return fit.lane_support_problem(r, own, 25.0, truth.attitude, true);
}

// On a bend a dashed lane's lines leave the view after a dash or two: both own lines
// may be single dashes (seven marks over 1.8 m each), when two other lines are fully
// supported (the solid edge lines, which give the road's direction) and each dash lies a
// lane's width from one of them. With one full line, or with a dash farther than a lane
// from every full line, the dashes make no lane.
TEST(LaneFit, BothOwnLinesMayBeADashBesideTwoFullLines) {
  const LaneEstimatorOptions o = options_without_gyro();
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(21);
  const LineMarks left_dash{1830.0, 14000.0, 15800.0, 300.0}, right_dash{-1830.0, 9000.0, 10800.0, 300.0};
  const LineMarks left_edge{5490.0, 6000.0, 40000.0, 1700.0}, right_edge{-5490.0, 6000.0, 40000.0, 1700.0};
  const LineMarks far_right{-9000.0, 6000.0, 40000.0, 1700.0};  // two lanes beyond the right dash
  const auto support = [&](const DetectionResult& detected) {
    DetectionResult d = detected;
    for (const int j : {0, 1}) d.lines[j].parallel = true;  // found beside the road's other lines
    LaneFit fit(o);
    EXPECT_TRUE(fit.take(d));
    const SolveResult& r = fit.solve(CameraPose{{}, truth.H_mm, truth.f_mm}, std::nullopt);
    EXPECT_TRUE(r.converged) << to_string(r.status);
    EXPECT_EQ(r.num_lines, d.num_lines);
    const OwnLane own{0, 1, r.lines[0].y0_mm - r.lines[1].y0_mm, 0.0, 0.0};
    return fit.lane_support_problem(r, own, 10.0, truth.attitude, true);
  };
  std::vector<Pick> picks;
  EXPECT_EQ(support(detection_of_lines(o, truth, {left_dash, right_dash, left_edge, right_edge}, rng, picks)),
            SupportProblem::none);
  EXPECT_EQ(support(detection_of_lines(o, truth, {left_dash, right_dash, left_edge}, rng, picks)),
            SupportProblem::too_few_marks)
      << "one full line";
  EXPECT_EQ(support(detection_of_lines(o, truth, {left_dash, right_dash, left_edge, far_right}, rng, picks)),
            SupportProblem::too_few_marks)
      << "the right dash two lanes from every full line";
}

// A lane of one full line and a row of dots: on a road with a single full line, the row
// is the lane's other line when its marks span enough road to have fitted their own slope
// (LineGrouper::kOwnSlopeSpanMm: two groups of dots), whether detection found it as the
// full line's parallel or as a line of its own a little short of a full line's reach. A
// shorter row, or paint found so (one dash, a short line), is not.
TEST(LaneFit, ARowOfDotsWithASlopeOfItsOwnMakesALaneBesideTheOnlyFullLine) {
  const LaneEstimatorOptions o = options_without_gyro();
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(11);
  struct Case {
    double from_mm, to_mm, step_mm;
    bool dots, parallel;
    SupportProblem expected;
  };
  for (const Case& c : {Case{6000.0, 15000.0, 1800.0, true, true, SupportProblem::none},           // 9 m of dots
                        Case{6000.0, 10000.0, 1000.0, true, true, SupportProblem::too_few_marks},  // 4 m
                        Case{6000.0, 15000.0, 1800.0, false, true, SupportProblem::too_few_marks},
                        Case{6000.0, 13000.0, 700.0, true, false, SupportProblem::none},  // 7 m, 11 marks
                        Case{6000.0, 13000.0, 700.0, false, false, SupportProblem::too_short}}) {
    std::vector<Pick> picks;
    DetectionResult d = detection_of_lines(
        o, truth, {{1830.0, 6000.0, 40000.0, 1700.0}, {-1830.0, c.from_mm, c.to_mm, c.step_mm}}, rng, picks);
    d.lines[1].parallel = c.parallel;
    d.lines[1].dots = c.dots;
    d.lines[1].near_mm = c.from_mm;
    d.lines[1].far_mm = c.to_mm - std::fmod(c.to_mm - c.from_mm, c.step_mm);
    // The full line's paint, 130 mm wide: narrower in pixels with distance.
    std::vector<MarkCandidate> paint;
    for (double x = 6000.0; x <= 40000.0; x += 1700.0) {
      MarkCandidate m;
      m.X = x;
      m.Y = 1830.0;
      m.line = 0;
      m.left_px = 400.0;
      m.right_px = 400.0 + 130.0 * 1000.0 / x;
      paint.push_back(m);
    }
    d.marks = paint;
    EXPECT_EQ(solved_lane_support(o, truth, d), c.expected)
        << "marks " << c.from_mm << " .. " << c.to_mm << " mm, dots " << c.dots << ", parallel " << c.parallel;
  }
}

// A line's bars must narrow with distance as paint of one width does: grey bars of one
// pixel width along a line are noise or a barrier's lip. A yellow line is paint whatever
// its bars' widths: its worn pale strip or a kerb's lit top beside it is taken in on some
// rows and not on others (TuSimple still 40: 9 to 21 px at one distance).
TEST(LaneFit, AYellowLineIsPaintWhateverItsBarsWidths) {
  const LaneEstimatorOptions o = options_without_gyro();
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(12);
  for (const bool yellow : {false, true}) {
    std::vector<Pick> picks;
    DetectionResult d = detection_of_lines(
        o, truth, {{1830.0, 6000.0, 40000.0, 1700.0}, {-1830.0, 6000.0, 40000.0, 1700.0}}, rng, picks);
    d.lines[0].yellow = yellow;
    // The right line's paint, 130 mm wide, narrower in pixels with distance; the left
    // line's bars 14 px wide at every distance.
    std::vector<MarkCandidate> bars;
    for (double x = 6000.0; x <= 40000.0; x += 1700.0)
      for (const int line : {0, 1}) {
        MarkCandidate m;
        m.X = x;
        m.Y = line == 0 ? 1830.0 : -1830.0;
        m.line = static_cast<std::int16_t>(line);
        m.yellow = yellow && line == 0;
        m.left_px = 400.0;
        m.right_px = 400.0 + (line == 0 ? 14.0 : 130.0 * 1000.0 / x);
        bars.push_back(m);
      }
    d.marks = bars;
    EXPECT_EQ(solved_lane_support(o, truth, d), yellow ? SupportProblem::none : SupportProblem::not_paint)
        << (yellow ? "yellow" : "grey");
  }
}

// One line alone does not fix the pitch: any pitch projects some road line onto its
// marks. Without a gyro, the solve takes the pitch of the pose it was looked for from (a
// search's, here 1 deg off the truth), converges there, and its line lies on the marks.
TEST(LaneFit, ASingleLineIsSolvedAtThePitchItWasLookedFrom) {
  LaneEstimatorOptions o = options_without_gyro();
  o.priors.theta_deg.reset();
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(13);
  std::vector<Pick> picks;
  const DetectionResult d = detection_of_lines(o, truth, {{1830.0, 6000.0, 40000.0, 1700.0}}, rng, picks);
  LaneFit fit(o);
  ASSERT_TRUE(fit.take(d));
  CameraPose looked_from = truth;
  looked_from.attitude.theta += deg_to_rad(1.0);
  const SolveResult& r = fit.solve(looked_from, std::nullopt);
  ASSERT_TRUE(r.converged) << to_string(r.status);
  EXPECT_NEAR(rad_to_deg(r.pose.attitude.theta), -1.0, 0.05);
  EXPECT_LT(r.rms_px, 2.0 * o.solver.pixel_sigma) << "the line lies on its marks";
}

// Without a gyro, a solve whose lines continue a track holds its roll by the frame
// before's as well as by the configured prior (LaneFit::set_previous_roll): their product,
// a Gaussian. Two lines with the lane-width prior leave the roll loosely held; the
// previous frame's roll 1 degree off the truth pulls the solve by what the Gaussians say,
// to first order its weight times the solve's own variance: 1 / 0.5^2 * sigma_phi^2
// degrees. A search's solve (no line continues a track) and a solve with a gyro are
// left as they were.
TEST(LaneFit, ATrackedSolveWithoutAGyroHoldsTheRollTheFrameBeforeSolved) {
  LaneEstimatorOptions o = options_without_gyro();
  o.priors.lane_width_mm = Prior{3660.0, 300.0};
  const CameraPose truth = truth_pose(o);
  std::mt19937_64 rng(31);
  std::vector<Pick> picks;
  DetectionResult d =
      detection_of_lines(o, truth, {{1830.0, 6000.0, 40000.0, 1700.0}, {-1830.0, 6000.0, 40000.0, 1700.0}}, rng, picks);
  const Prior previous{1.0, 0.5};
  const auto solved_roll = [&](const DetectionResult& detected, bool with_previous,
                               const std::optional<Gx1Angles>& gyro, double* sigma = nullptr) {
    LaneFit fit(o);
    EXPECT_TRUE(fit.take(detected));
    if (with_previous) fit.set_previous_roll(previous);
    const SolveResult& r = fit.solve(truth, gyro);
    EXPECT_TRUE(r.converged) << to_string(r.status);
    if (sigma) *sigma = r.sigma.phi_deg;
    return rad_to_deg(r.pose.attitude.phi);
  };
  // A search's lines: the frame before says nothing.
  EXPECT_DOUBLE_EQ(solved_roll(d, true, std::nullopt), solved_roll(d, false, std::nullopt));
  // Tracked lines.
  d.lines[0].prior_index = 0;
  d.lines[1].prior_index = 1;
  double sigma = 0.0;
  const double held = solved_roll(d, true, std::nullopt, &sigma), free = solved_roll(d, false, std::nullopt);
  ASSERT_GT(sigma, 0.0);
  ASSERT_LT(sigma, 0.5);
  const double expected_pull = (previous.mean - free) * sigma * sigma / (previous.sigma * previous.sigma);
  EXPECT_GT(held - free, 0.05) << "the frame before pulls the roll";
  EXPECT_NEAR(held - free, expected_pull, 0.2 * expected_pull) << "sigma_phi " << sigma;
  // A gyro measures the roll: the frame before is not asked.
  const Gx1Angles gyro{0.0, -rad_to_deg(truth.attitude.theta), 0.0};
  EXPECT_DOUBLE_EQ(solved_roll(d, true, gyro), solved_roll(d, false, gyro));
}

}  // namespace
}  // namespace ccdlane
