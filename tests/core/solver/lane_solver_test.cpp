// LaneSolver against known truth: exact recovery without noise in both modes, errors
// consistent with the reported covariance under noise (Monte Carlo NEES), honest rank
// deficiency, rejected input, warm starts, and the seed paper's picture (a).
#include "core/solver/lane_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "core/solver/picks_csv.hpp"
#include "tests/core/solver/synthetic_scene.hpp"

namespace ccdlane {
namespace {

using test::free_set;
using test::SceneOptions;
using test::SyntheticScene;

// A request for `scene` from a cold start as a gyro gives it: zero yaw, pitch and roll
// 1 degree off the truth, the true H and f, lines fitted. (At zero pitch and roll the
// rays of far marks can miss the road: see PickAboveTheHorizonHasNoGroundPoint.)
SolveRequest cold_request(const SyntheticScene& scene, std::span<const Pick> picks, FreeSet free,
                          SolverMode mode = SolverMode::reprojection) {
  SolveRequest r;
  r.mode = mode;
  r.free = free;
  r.initial_pose = scene.truth;
  r.initial_pose.attitude = {0.0, scene.truth.attitude.theta + deg_to_rad(1.0),
                             scene.truth.attitude.phi - deg_to_rad(1.0)};
  r.picks = picks;
  r.num_lines = static_cast<int>(scene.lines.size());
  return r;
}

// Fixed parameters must hold their true value: start them there.
void start_fixed_at_truth(SolveRequest& r, const SyntheticScene& scene, std::vector<RoadLine>& lines) {
  const Attitude& t = scene.truth.attitude;
  if (!r.free.has(FreeParam::psi)) r.initial_pose.attitude.psi = t.psi;
  if (!r.free.has(FreeParam::theta)) r.initial_pose.attitude.theta = t.theta;
  if (!r.free.has(FreeParam::phi)) r.initial_pose.attitude.phi = t.phi;
  const bool straight = std::all_of(scene.lines.begin(), scene.lines.end(),
                                    [](const RoadLine& l) { return l.m == 0.0 && l.c_per_mm == 0.0; });
  if (straight) return;  // the solver's own fit (m = 0, c = 0) then starts fixed kinds right
  // Lines given: free kinds start from a rough guess, fixed ones at the truth.
  lines = scene.lines;
  for (RoadLine& l : lines) {
    if (r.free.has(FreeParam::y0)) l.y0_mm += 300.0;
    if (r.free.has(FreeParam::m)) l.m = 0.0;
    if (r.free.has(FreeParam::c)) l.c_per_mm = 0.0;
  }
  r.initial_lines = lines;
}

// Largest error of the result against the truth, per kind, in interface units; for the
// lines the lateral error anywhere in 0..40 m ahead.
struct TruthErrors {
  double angle_deg = 0, H_mm = 0, f_mm = 0, line_mm = 0, x_rel = 0;
};

TruthErrors errors_against_truth(const SolveResult& res, const SyntheticScene& scene) {
  TruthErrors e;
  const Attitude &a = res.pose.attitude, &t = scene.truth.attitude;
  e.angle_deg = rad_to_deg(std::max({std::abs(a.psi - t.psi), std::abs(a.theta - t.theta), std::abs(a.phi - t.phi)}));
  e.H_mm = std::abs(res.pose.H_mm - scene.truth.H_mm);
  e.f_mm = std::abs(res.pose.f_mm - scene.truth.f_mm);
  for (std::size_t j = 0; j < scene.lines.size(); ++j)
    for (double x = 0; x <= 40000.0; x += 5000.0) {
      const RoadLine &l = res.lines[j], &tl = scene.lines[j];
      e.line_mm = std::max(
          e.line_mm, std::abs((l.y0_mm + l.m * x + l.c_per_mm * x * x) - (tl.y0_mm + tl.m * x + tl.c_per_mm * x * x)));
    }
  for (std::size_t i = 0; i < scene.x_mm.size(); ++i)
    e.x_rel = std::max(e.x_rel, std::abs(res.points_mm[i].x() - scene.x_mm[i]) / scene.x_mm[i]);
  return e;
}

void expect_truth_recovered(const SolveResult& res, const SyntheticScene& scene, const std::string& what) {
  ASSERT_TRUE(res.converged) << what << ": " << to_string(res.status);
  EXPECT_FALSE(res.rank_deficient) << what;
  const TruthErrors e = errors_against_truth(res, scene);
  EXPECT_LT(e.angle_deg, 1e-6) << what;
  EXPECT_LT(e.H_mm, 1e-6) << what;
  EXPECT_LT(e.f_mm, 1e-6) << what;
  EXPECT_LT(e.line_mm, 1e-6) << what;
  EXPECT_LT(e.x_rel, 1e-9) << what;
  EXPECT_LT(res.rms_px, 1e-6) << what;
}

// Sanitizer builds (instrumented, at -O1 or unoptimised: ~100x slower per solve) draw
// fewer scenes; every bound below is derived from the number of draws actually made.
#ifdef CCDLANE_SOLVER_FEW_DRAWS
constexpr int kDraws = 25, kTruthDraws = 3;
#else
constexpr int kDraws = 300, kTruthDraws = 8;
#endif

struct ZeroNoiseCase {
  const char* name;
  FreeSet free;
  SceneOptions scene;
  bool roll_prior = false, height_prior = false, focal_prior = false;
};

std::vector<ZeroNoiseCase> zero_noise_cases() {
  using enum FreeParam;
  SceneOptions curved;
  curved.max_slope = 0.03;
  curved.max_curvature = 2e-6;  // radius >= 250 m
  SceneOptions three;
  three.num_lines = 3;
  // Yaw and a free heading m of every line are one unknown (turning the camera about the
  // vertical through its mount is turning the road): never both free in a well-posed case.
  return {
      {"attitude+y0, roll prior", free_set({psi, theta, phi, y0}), {}, true},
      {"attitude+y0, 3 lines, roll prior", free_set({psi, theta, phi, y0}), three, true},
      {"pitch roll + y0 m c, roll prior", free_set({theta, phi, y0, m, c}), curved, true},
      {"all globals + y0, priors", free_set({psi, theta, phi, H, f, y0}), {}, true, true, true},
      {"yaw pitch + y0, roll fixed", free_set({psi, theta, y0}), {}},
  };
}

TEST(LaneSolverTruth, ZeroNoiseRecoversTruthInReprojectionMode) {
  std::mt19937_64 rng(11);
  LaneSolver solver(test::reference_camera(), 64);
  for (const ZeroNoiseCase& c : zero_noise_cases())
    for (int draw = 0; draw < kTruthDraws; ++draw) {
      const SyntheticScene scene = test::make_scene(rng, c.scene);
      SolveRequest r = cold_request(scene, scene.picks, c.free);
      std::vector<RoadLine> lines;
      start_fixed_at_truth(r, scene, lines);
      // Priors centred on the truth are consistent with noise-free picks.
      if (c.roll_prior) r.priors.phi_deg = Prior{rad_to_deg(scene.truth.attitude.phi), 0.5};
      if (c.height_prior) {
        r.priors.H_mm = Prior{scene.truth.H_mm, 20.0};
        r.initial_pose.H_mm += 30.0;
      }
      if (c.focal_prior) {
        r.priors.f_mm = Prior{scene.truth.f_mm, 0.05};
        r.initial_pose.f_mm += 0.05;
      }
      expect_truth_recovered(solver.solve(r), scene, std::string(c.name) + " draw " + std::to_string(draw));
    }
}

TEST(LaneSolverTruth, ZeroNoiseRecoversTruthInPaperModeAndModesAgree) {
  using enum FreeParam;
  std::mt19937_64 rng(12);
  LaneSolver paper(test::reference_camera(), 64), reprojection(test::reference_camera(), 64);
  // The paper's algebraic index has local minima far from the truth (e.g. toward yaw
  // +-90 degrees, where its residuals shrink with the rays' x extent): gentler roads.
  SceneOptions curved;
  curved.max_slope = 0.01;
  curved.max_curvature = 5e-7;  // radius >= 1 km
  const std::pair<FreeSet, SceneOptions> cases[] = {
      {free_set({psi, theta, y0}), {}},
      {free_set({psi, theta, y0}), curved},
      {free_set({psi, theta, y0, c}), curved},
  };
  for (const auto& [free, options] : cases)
    for (int draw = 0; draw < kTruthDraws; ++draw) {
      const SyntheticScene scene = test::make_scene(rng, options);
      std::vector<RoadLine> lines;
      SolveRequest r = cold_request(scene, scene.picks, free, SolverMode::paper);
      start_fixed_at_truth(r, scene, lines);
      const SolveResult& p = paper.solve(r);
      expect_truth_recovered(p, scene, "paper draw " + std::to_string(draw));
      r.mode = SolverMode::reprojection;
      const SolveResult& q = reprojection.solve(r);
      expect_truth_recovered(q, scene, "reprojection draw " + std::to_string(draw));
      EXPECT_NEAR(rad_to_deg(p.pose.attitude.psi), rad_to_deg(q.pose.attitude.psi), 2e-6);
      EXPECT_NEAR(p.lines[0].y0_mm, q.lines[0].y0_mm, 2e-6);
    }
}

// Normalised estimation error squared of the free parameters against the truth, with
// the solver's own covariance: chi-square with num_free degrees of freedom when both the
// optimum and the covariance are right (to first order in the noise).
double nees(const SolveResult& res, const SyntheticScene& scene) {
  const int n = res.num_free;
  Eigen::VectorXd e(n);
  for (int k = 0; k < n; ++k) {
    const ReducedParam p = res.free_params[k];
    const Attitude &a = res.pose.attitude, &t = scene.truth.attitude;
    switch (p.kind) {
      case FreeParam::psi: e[k] = a.psi - t.psi; break;
      case FreeParam::theta: e[k] = a.theta - t.theta; break;
      case FreeParam::phi: e[k] = a.phi - t.phi; break;
      case FreeParam::H: e[k] = res.pose.H_mm - scene.truth.H_mm; break;
      case FreeParam::f: e[k] = res.pose.f_mm - scene.truth.f_mm; break;
      case FreeParam::y0: e[k] = res.lines[p.line].y0_mm - scene.lines[p.line].y0_mm; break;
      case FreeParam::m: e[k] = res.lines[p.line].m - scene.lines[p.line].m; break;
      case FreeParam::c: {
        const int line = std::max(p.line, 0);  // a shared curvature: in every line
        e[k] = res.lines[line].c_per_mm - scene.lines[line].c_per_mm;
        break;
      }
    }
  }
  const Eigen::MatrixXd cov = res.covariance.topLeftCorner(n, n);
  return e.dot(cov.ldlt().solve(e));
}

struct MonteCarloSetup {
  FreeSet free;
  SceneOptions scene;
  bool height_prior = false;
};

// Quantile of the chi-square distribution with k degrees of freedom at the standard
// normal quantile z (Wilson-Hilferty: relative error < 1e-3 for k >= 30).
double chi_square_quantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

// Runs kDraws random scenes with Gaussian pick noise (sigma = pixel_sigma) and gyro-like
// priors whose means are themselves noisy measurements of the truth, and checks the
// summed NEES. Bound: the draws are independent, so over D = sum of num_free the sum of
// their NEES is chi-square with D degrees of freedom (mean D, variance 2D); the test
// accepts its central 99.9% (z = 3.29 each side): for 300 draws of 5 parameters a mean
// NEES per parameter within about 1 +- 0.12.
void run_monte_carlo(const MonteCarloSetup& setup, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  constexpr double kPixelSigma = 0.5, kGyroSigmaDeg = 0.5, kHeightSigmaMm = 20.0;
  LaneSolver solver(test::reference_camera(), 64);
  double nees_sum = 0.0, dof = 0.0;
  for (int draw = 0; draw < kDraws; ++draw) {
    const SyntheticScene scene = test::make_scene(rng, setup.scene);
    const std::vector<Pick> picks = test::noisy_picks(scene, kPixelSigma, rng);
    SolveRequest r = cold_request(scene, picks, setup.free);
    std::vector<RoadLine> lines;
    start_fixed_at_truth(r, scene, lines);
    r.pixel_sigma = kPixelSigma;
    r.priors.theta_deg = Prior{rad_to_deg(scene.truth.attitude.theta) + kGyroSigmaDeg * unit(rng), kGyroSigmaDeg};
    r.priors.phi_deg = Prior{rad_to_deg(scene.truth.attitude.phi) + kGyroSigmaDeg * unit(rng), kGyroSigmaDeg};
    if (setup.height_prior) r.priors.H_mm = Prior{scene.truth.H_mm + kHeightSigmaMm * unit(rng), kHeightSigmaMm};
    const SolveResult& res = solver.solve(r);
    ASSERT_TRUE(res.converged) << "draw " << draw << ": " << to_string(res.status);
    ASSERT_FALSE(res.rank_deficient) << "draw " << draw;
    nees_sum += nees(res, scene);
    dof += res.num_free;
  }
  const std::string report =
      "mean NEES per parameter " + std::to_string(nees_sum / dof) + " over " + std::to_string(kDraws) + " draws";
  EXPECT_GT(nees_sum, chi_square_quantile(dof, -3.29)) << report;
  EXPECT_LT(nees_sum, chi_square_quantile(dof, 3.29)) << report;
}

TEST(LaneSolverMonteCarlo, NeesMatchesFreeParametersForAttitudeAndOffsets) {
  using enum FreeParam;
  MonteCarloSetup setup{free_set({psi, theta, phi, y0}), {}};
  run_monte_carlo(setup, 2024);
  setup.scene.num_lines = 3;
  run_monte_carlo(setup, 2026);
}

TEST(LaneSolverMonteCarlo, NeesMatchesFreeParametersWithHeight) {
  using enum FreeParam;
  MonteCarloSetup setup{free_set({psi, theta, phi, H, y0}), {}, true};
  run_monte_carlo(setup, 2025);
}

// A bend (radius 300-2000 m, left or right) seen as the reference camera sees it: marks
// 5-40 m ahead on two lines, the default free set with a roll prior.
SceneOptions bend(double min_radius_mm = 300e3, double max_radius_mm = 2000e3) {
  SceneOptions o;
  o.min_radius_mm = min_radius_mm;
  o.max_radius_mm = max_radius_mm;
  return o;
}

TEST(LaneSolverCurve, ZeroNoiseRecoversABendWithOneSharedCurvature) {
  using enum FreeParam;
  std::mt19937_64 rng(61);
  LaneSolver solver(test::reference_camera(), 64);
  SceneOptions three = bend();
  three.num_lines = 3;
  for (const SceneOptions& options : {bend(), three})
    for (int draw = 0; draw < kTruthDraws; ++draw) {
      const SyntheticScene scene = test::make_scene(rng, options);
      SolveRequest r = cold_request(scene, scene.picks, free_set({psi, theta, phi, y0}));
      r.line_model = LineModel::shared_curvature;
      r.priors.phi_deg = Prior{rad_to_deg(scene.truth.attitude.phi), 0.5};
      const std::string what = "draw " + std::to_string(draw);
      const SolveResult& res = solver.solve(r);
      expect_truth_recovered(res, scene, what);
      // One c, reported in every line, with its sigma; and the bend's radius.
      for (int j = 0; j < res.num_lines; ++j) {
        EXPECT_NEAR(res.lines[j].c_per_mm, scene.lines[j].c_per_mm, 1e-9 * std::abs(scene.lines[j].c_per_mm)) << what;
        EXPECT_TRUE(std::isfinite(res.sigma.c_per_mm[j]) && res.sigma.c_per_mm[j] > 0.0) << what;
      }
      const double radius = 1.0 / (2.0 * scene.lines[0].c_per_mm);  // the truth has m = 0
      EXPECT_NEAR(radius_of_curvature_mm(res.lines[0]), radius, 1e-6 * std::abs(radius)) << what;
      EXPECT_EQ(res.free_params[res.num_free - res.num_lines - 1].kind, c) << "c after the globals";
    }
  // The paper's index takes the same model (gentler bends: its local minima, see above).
  for (int draw = 0; draw < kTruthDraws; ++draw) {
    const SyntheticScene scene = test::make_scene(rng, bend(1000e3, 2000e3));
    std::vector<RoadLine> lines;
    SolveRequest r = cold_request(scene, scene.picks, free_set({psi, theta, y0}), SolverMode::paper);
    r.line_model = LineModel::shared_curvature;
    start_fixed_at_truth(r, scene, lines);
    expect_truth_recovered(solver.solve(r), scene, "paper draw " + std::to_string(draw));
  }
}

// The errors of one model over the bend study's draws, each normalised by the sigma the
// solver reports for it: z = error / sigma, N(0, 1) per draw when the model is right.
struct BendErrors {
  double yaw_bias_deg = 0.0;      // mean of sign(c) * yaw error: a bias that follows the bend
  double z_yaw = 0.0, z_c = 0.0;  // means of sign(c) * z
  double max_abs_z = 0.0;         // over yaw, pitch, roll, y0 and c of every draw
  double nees = 0.0, dof = 0.0;   // summed over the draws
};

// Solves kDraws noisy bends (pixel noise 0.5 px, gyro pitch and roll priors of 0.5 deg
// as in run_monte_carlo) with `model`, free yaw, pitch, roll and y0.
BendErrors bend_errors(LineModel model, std::uint64_t seed) {
  using enum FreeParam;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  constexpr double kPixelSigma = 0.5, kGyroSigmaDeg = 0.5;
  LaneSolver solver(test::reference_camera(), 64);
  BendErrors out;
  for (int draw = 0; draw < kDraws; ++draw) {
    const SyntheticScene scene = test::make_scene(rng, bend());
    const std::vector<Pick> picks = test::noisy_picks(scene, kPixelSigma, rng);
    SolveRequest r = cold_request(scene, picks, free_set({psi, theta, phi, y0}));
    r.line_model = model;
    r.pixel_sigma = kPixelSigma;
    r.priors.theta_deg = Prior{rad_to_deg(scene.truth.attitude.theta) + kGyroSigmaDeg * unit(rng), kGyroSigmaDeg};
    r.priors.phi_deg = Prior{rad_to_deg(scene.truth.attitude.phi) + kGyroSigmaDeg * unit(rng), kGyroSigmaDeg};
    const SolveResult& res = solver.solve(r);
    EXPECT_TRUE(res.converged) << "draw " << draw << ": " << to_string(res.status);
    EXPECT_FALSE(res.rank_deficient) << "draw " << draw;
    if (!res.converged || res.rank_deficient) continue;
    const double side = scene.lines[0].c_per_mm > 0.0 ? 1.0 : -1.0;
    const double yaw_error_deg = rad_to_deg(res.pose.attitude.psi - scene.truth.attitude.psi);
    out.yaw_bias_deg += side * yaw_error_deg / kDraws;
    out.z_yaw += side * yaw_error_deg / res.sigma.psi_deg / kDraws;
    const double z[] = {yaw_error_deg / res.sigma.psi_deg,
                        rad_to_deg(res.pose.attitude.theta - scene.truth.attitude.theta) / res.sigma.theta_deg,
                        rad_to_deg(res.pose.attitude.phi - scene.truth.attitude.phi) / res.sigma.phi_deg,
                        (res.lines[0].y0_mm - scene.lines[0].y0_mm) / res.sigma.y0_mm[0],
                        (res.lines[1].y0_mm - scene.lines[1].y0_mm) / res.sigma.y0_mm[1]};
    for (const double zk : z) out.max_abs_z = std::max(out.max_abs_z, std::abs(zk));
    if (model == LineModel::shared_curvature) {
      const double z_c = (res.lines[0].c_per_mm - scene.lines[0].c_per_mm) / res.sigma.c_per_mm[0];
      out.z_c += side * z_c / kDraws;
      out.max_abs_z = std::max(out.max_abs_z, std::abs(z_c));
    }
    out.nees += nees(res, scene);
    out.dof += res.num_free;
  }
  return out;
}

// Against the truth of noisy bends, with bounds from the pixel noise through the solver's
// own covariance. Per draw and parameter z = error / sigma is N(0, 1): |z| <= 5 for all
// of kDraws x 6 of them fails a right solver with probability 1800 x 5.7e-7 = 1e-3. The
// mean of sign(c) z over the draws is N(0, 1 / kDraws): a bias that follows the bend is
// rejected beyond 3.29 / sqrt(kDraws) (two-sided 1e-3), and the summed NEES is held to
// the central 99.9% of its chi-square distribution, as in run_monte_carlo.
TEST(LaneSolverCurve, SharedCurvatureIsUnbiasedOnABendWhereStraightLinesBiasYaw) {
  const double mean_bound = 3.29 / std::sqrt(static_cast<double>(kDraws));
  const BendErrors curved = bend_errors(LineModel::shared_curvature, 2027);
  EXPECT_LT(curved.max_abs_z, 5.0);
  EXPECT_LT(std::abs(curved.z_yaw), mean_bound);
  EXPECT_LT(std::abs(curved.z_c), mean_bound);
  EXPECT_GT(curved.nees, chi_square_quantile(curved.dof, -3.29));
  EXPECT_LT(curved.nees, chi_square_quantile(curved.dof, 3.29));
  // The same draws (same seed) with straight lines: each line's fit takes the heading of
  // a chord of the bend, about c (x_near + x_far), for the road's, and yaw comes out
  // turned away from the bend by that much, far outside what its sigma allows (the test
  // the curved model passes, failed).
  const BendErrors straight = bend_errors(LineModel::per_line, 2027);
  EXPECT_GT(std::abs(straight.z_yaw), mean_bound);
  std::printf(
      "bend R 300-2000 m, %d draws: mean sign(c) * yaw error %+.4f deg straight (mean z %+.1f, NEES/dof "
      "%.1f), %+.5f deg curved (mean z %+.3f, c %+.3f, NEES/dof %.3f, max |z| %.2f); bound |mean z| < %.3f\n",
      kDraws, straight.yaw_bias_deg, straight.z_yaw, straight.nees / straight.dof, curved.yaw_bias_deg, curved.z_yaw,
      curved.z_c, curved.nees / curved.dof, curved.max_abs_z, mean_bound);
}

TEST(LaneSolverCurve, MarksAtTwoDistancesLeaveTheCurvatureUndetermined) {
  // Per line each distance gives one equation (where the line crosses it; x_i takes the
  // other): 2 lines x 2 distances + the roll prior = 5 against yaw, pitch, roll, 2 y0
  // and c. Straight lines (5 unknowns) are determined; c needs a third distance.
  using enum FreeParam;
  std::mt19937_64 rng(62);
  LaneSolver solver(test::reference_camera(), 64);
  SceneOptions two = bend(500e3, 500e3);
  two.mark_distances_mm = {10000.0, 25000.0};
  SceneOptions three = two;
  three.mark_distances_mm = {10000.0, 18000.0, 25000.0};
  for (int draw = 0; draw < kTruthDraws; ++draw) {
    const SyntheticScene at_two = test::make_scene(rng, two);
    SolveRequest r = cold_request(at_two, at_two.picks, free_set({psi, theta, phi, y0}));
    r.priors.phi_deg = Prior{rad_to_deg(at_two.truth.attitude.phi), 0.5};
    r.line_model = LineModel::shared_curvature;
    const SolveResult& curved = solver.solve(r);
    EXPECT_TRUE(curved.rank_deficient) << "draw " << draw;
    EXPECT_TRUE(std::isnan(curved.sigma.c_per_mm[0]));
    EXPECT_TRUE(std::isnan(curved.sigma.psi_deg));
    r.line_model = LineModel::per_line;
    EXPECT_FALSE(solver.solve(r).rank_deficient) << "draw " << draw;

    const SyntheticScene at_three = test::make_scene(rng, three);
    r = cold_request(at_three, at_three.picks, r.free);
    r.priors.phi_deg = Prior{rad_to_deg(at_three.truth.attitude.phi), 0.5};
    r.line_model = LineModel::shared_curvature;
    const SolveResult& determined = solver.solve(r);
    EXPECT_FALSE(determined.rank_deficient) << "draw " << draw;
    EXPECT_TRUE(std::isfinite(determined.sigma.c_per_mm[1]));
  }
}

TEST(LaneSolverRank, FreeRollWithFreeOffsetsIsReportedRankDeficient) {
  using enum FreeParam;
  std::mt19937_64 rng(31);
  LaneSolver solver(test::reference_camera(), 64);
  for (int draw = 0; draw < kTruthDraws; ++draw) {
    const SyntheticScene scene = test::make_scene(rng, {});
    const std::vector<Pick> picks = test::noisy_picks(scene, 0.5, rng);
    SolveRequest r = cold_request(scene, picks, free_set({psi, theta, phi, y0}));
    const SolveResult& res = solver.solve(r);
    EXPECT_TRUE(res.rank_deficient) << "draw " << draw;
    EXPECT_TRUE(std::isnan(res.sigma.phi_deg));
    EXPECT_TRUE(std::isnan(res.sigma.y0_mm[0]));
    EXPECT_TRUE(std::isnan(res.sigma.y0_mm[1]));
    // With a roll prior the same picks determine everything.
    r.priors.phi_deg = Prior{0.0, 5.0};
    const SolveResult& fixed = solver.solve(r);
    EXPECT_TRUE(fixed.converged);
    EXPECT_FALSE(fixed.rank_deficient) << "draw " << draw;
    EXPECT_TRUE(std::isfinite(fixed.sigma.phi_deg) && fixed.sigma.phi_deg > 0.0);
    EXPECT_TRUE(std::isfinite(fixed.sigma.y0_mm[1]) && fixed.sigma.y0_mm[1] > 0.0);
  }
}

TEST(LaneSolverRank, FreeHeightWithoutPriorIsScaleAmbiguous) {
  // Scaling the road about the point under the lens leaves the picture unchanged.
  using enum FreeParam;
  std::mt19937_64 rng(32);
  LaneSolver solver(test::reference_camera(), 64);
  const SyntheticScene scene = test::make_scene(rng, {});
  SolveRequest r = cold_request(scene, scene.picks, free_set({psi, theta, H, y0}));
  r.initial_pose.attitude.phi = scene.truth.attitude.phi;
  const SolveResult& res = solver.solve(r);
  EXPECT_TRUE(res.rank_deficient);
  EXPECT_TRUE(std::isnan(res.sigma.H_mm));
  EXPECT_TRUE(std::isnan(res.sigma.y0_mm[0]));
  // The attitude is still determined: the family is a pure scaling.
  EXPECT_TRUE(std::isfinite(res.sigma.psi_deg));
  EXPECT_TRUE(std::isfinite(res.sigma.theta_deg));
}

TEST(LaneSolverRank, FreeHeadingsOfStraightLinesLeaveYawAndPitchUndetermined) {
  // Attitude comes from the lines being parallel: with a free heading m per line, every
  // picked image line back-projects onto some road line at any yaw and pitch.
  using enum FreeParam;
  std::mt19937_64 rng(33);
  LaneSolver solver(test::reference_camera(), 64);
  const SyntheticScene scene = test::make_scene(rng, {});
  const std::vector<Pick> picks = test::noisy_picks(scene, 0.5, rng);
  SolveRequest r = cold_request(scene, picks, free_set({psi, theta, phi, y0, m}));
  r.priors.phi_deg = Prior{rad_to_deg(scene.truth.attitude.phi), 0.5};
  const SolveResult& res = solver.solve(r);
  EXPECT_TRUE(res.rank_deficient);
  EXPECT_TRUE(std::isnan(res.sigma.psi_deg));
  EXPECT_TRUE(std::isnan(res.sigma.theta_deg));
  EXPECT_TRUE(std::isnan(res.sigma.m[0]));
  EXPECT_TRUE(std::isnan(res.sigma.m[1]));
  // Roll has its prior; with yaw and pitch given, the headings are determined again.
  r.free = free_set({phi, y0, m});
  r.initial_pose.attitude = scene.truth.attitude;
  const SolveResult& fixed = solver.solve(r);
  EXPECT_FALSE(fixed.rank_deficient);
  EXPECT_TRUE(std::isfinite(fixed.sigma.m[0]));
}

class LaneSolverInput : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937_64 rng(41);
    scene = test::make_scene(rng, {});
    picks = scene.picks;
    request = cold_request(scene, picks, SolverConfig::default_free());
    request.priors.phi_deg = Prior{0.0, 1.0};
  }
  SyntheticScene scene;
  std::vector<Pick> picks;
  SolveRequest request;
  LaneSolver solver{test::reference_camera(), 40};
};

TEST_F(LaneSolverInput, WellFormedRequestSolves) { EXPECT_TRUE(solver.solve(request).converged); }

TEST_F(LaneSolverInput, NanOrInfinitePickIsRejected) {
  for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
    picks[7].py = bad;
    request.picks = picks;
    const SolveResult& res = solver.solve(request);
    EXPECT_EQ(res.status, SolveStatus::invalid_input);
    EXPECT_EQ(res.failed_pick, 7);
    EXPECT_FALSE(res.converged);
  }
}

TEST_F(LaneSolverInput, NonFiniteSettingsAreRejected) {
  const auto expect_invalid = [&](SolveRequest r, const char* what) {
    EXPECT_EQ(solver.solve(r).status, SolveStatus::invalid_input) << what;
  };
  SolveRequest r = request;
  r.initial_pose.attitude.theta = std::nan("");
  expect_invalid(r, "NaN pitch");
  r = request;
  r.initial_pose.H_mm = HUGE_VAL;
  expect_invalid(r, "infinite H");
  r = request;
  r.pixel_sigma = 0.0;
  expect_invalid(r, "zero pixel sigma");
  r = request;
  r.priors.theta_deg = Prior{std::nan(""), 1.0};
  expect_invalid(r, "NaN prior mean");
  r = request;
  r.priors.theta_deg = Prior{0.0, -1.0};
  expect_invalid(r, "negative prior sigma");
  const RoadLine lines[2] = {{1750.0, 0.0, 0.0}, {std::nan(""), 0.0, 0.0}};
  r = request;
  r.initial_lines = lines;
  expect_invalid(r, "NaN initial line");
  r.initial_lines = std::span<const RoadLine>(lines, 1);
  expect_invalid(r, "one initial line for two lines");
}

TEST_F(LaneSolverInput, NothingFreeIsRejected) {
  // Once a Debug build aborted here on an Eigen bounds check, and a Release build wrote
  // outside the empty reduced system and reported converged_step.
  request.free = FreeSet{};
  for (const SolverMode mode : {SolverMode::reprojection, SolverMode::paper}) {
    request.mode = mode;
    const SolveResult& res = solver.solve(request);
    EXPECT_EQ(res.status, SolveStatus::invalid_input) << to_string(res.status);
    EXPECT_FALSE(res.converged);
    EXPECT_EQ(res.num_free, 0);
  }
}

TEST_F(LaneSolverInput, CurvaturePerLineAndSharedAtOnceIsRejected) {
  request.line_model = LineModel::shared_curvature;
  EXPECT_TRUE(solver.solve(request).converged);
  request.free.add(FreeParam::c);
  EXPECT_EQ(solver.solve(request).status, SolveStatus::invalid_input);
}

TEST_F(LaneSolverInput, LineIdsAndSizesOutOfRangeAreRejected) {
  picks[3].line = 2;  // only lines 0 and 1
  request.picks = picks;
  EXPECT_EQ(solver.solve(request).status, SolveStatus::invalid_input);
  EXPECT_EQ(solver.solve(request).failed_pick, 3);
  picks[3].line = -1;
  EXPECT_EQ(solver.solve(request).status, SolveStatus::invalid_input);
  picks[3].line = 0;
  request.num_lines = kMaxLaneLines + 1;
  EXPECT_EQ(solver.solve(request).status, SolveStatus::invalid_input);
  request.num_lines = 2;
  const std::vector<Pick> many(41, picks[0]);  // capacity is 40
  request.picks = many;
  EXPECT_EQ(solver.solve(request).status, SolveStatus::invalid_input);
}

TEST_F(LaneSolverInput, TooFewPicksForTheUnknowns) {
  // psi theta phi + 2 y0 = 5 unknowns, one free prior (phi): at least 4 picks.
  EXPECT_EQ(required_picks(request), 4);
  request.picks = std::span<const Pick>(picks).first(3);
  EXPECT_EQ(solver.solve(request).status, SolveStatus::too_few_picks);
  request.picks = std::span<const Pick>(picks).first(4);
  EXPECT_NE(solver.solve(request).status, SolveStatus::too_few_picks);
  // The paper's index takes no priors: the same picks are then too few.
  request.mode = SolverMode::paper;
  EXPECT_EQ(required_picks(request), 5);
  EXPECT_EQ(solver.solve(request).status, SolveStatus::too_few_picks);
}

TEST_F(LaneSolverInput, PickAboveTheHorizonHasNoGroundPoint) {
  picks[5].py = 20.0;  // near the top of the picture at zero pitch: sky
  request.picks = picks;
  const SolveResult& res = solver.solve(request);
  EXPECT_EQ(res.status, SolveStatus::no_ground_point);
  EXPECT_EQ(res.failed_pick, 5);
}

TEST(LaneSolverWarmStart, NextFrameConvergesInFewIterations) {
  using enum FreeParam;
  std::mt19937_64 rng(51);
  LaneSolver solver(test::reference_camera(), 64);
  for (int draw = 0; draw < kTruthDraws; ++draw) {
    const SyntheticScene scene = test::make_scene(rng, {});
    const std::vector<Pick> frame1 = test::noisy_picks(scene, 0.5, rng), frame2 = test::noisy_picks(scene, 0.5, rng);
    SolveRequest r = cold_request(scene, frame1, free_set({psi, theta, phi, y0}));
    r.priors.phi_deg = Prior{rad_to_deg(scene.truth.attitude.phi), 0.5};
    r.priors.theta_deg = Prior{rad_to_deg(scene.truth.attitude.theta), 0.5};
    const SolveResult& cold = solver.solve(r);
    ASSERT_TRUE(cold.converged);
    const int cold_iterations = cold.iterations;
    const CameraPose pose = cold.pose;
    const std::vector<RoadLine> lines(cold.lines.begin(), cold.lines.begin() + cold.num_lines);

    r.picks = frame2;
    r.initial_pose = pose;
    r.initial_lines = lines;
    r.warm_start = true;
    const SolveResult& warm = solver.solve(r);
    EXPECT_TRUE(warm.converged) << to_string(warm.status);
    EXPECT_LE(warm.iterations, 5);
    EXPECT_LT(warm.iterations, cold_iterations);
    // Same optimum as a cold start on frame 2, to within the stopping rule: a relative
    // cost change of 1e-12 leaves the parameters within ~sqrt(1e-12 J) ~ 1e-5 sigma.
    const double warm_psi = warm.pose.attitude.psi, warm_cost = warm.cost;
    const double psi_tolerance = 1e-5 * deg_to_rad(warm.sigma.psi_deg);
    r.initial_pose = cold_request(scene, frame2, r.free).initial_pose;
    r.initial_lines = {};
    r.warm_start = false;
    const SolveResult& again = solver.solve(r);
    EXPECT_NEAR(warm_psi, again.pose.attitude.psi, psi_tolerance);
    EXPECT_NEAR(warm_cost, again.cost, 2e-12 * again.cost);
  }
}

// The seed paper's picture (a), with the settings of tests/data/paper/README.md. The picture
// does not fix the scale (FreeHeightWithoutPriorIsScaleAmbiguous): y0 comes out in
// proportion to the lens height above the road, H - yM at zero attitude.
class PaperTable1a : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string path = std::string(CCDLANE_TEST_DATA_DIR) + "/paper/table1_a.csv";
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    std::stringstream text;
    text << in.rdbuf();
    picks = parse_picks_csv(text.str(), path).picks;
    camera = test::reference_camera();
    camera.cx = 385.0;
    camera.cy = 313.2;
  }
  SolveRequest request(double H_mm) const {
    using enum FreeParam;
    SolveRequest r;
    r.free = free_set({psi, theta, phi, y0});  // m fixed at 0 (no initial lines: m = 0)
    r.priors.theta_deg = Prior{0.0, 1.0};
    r.priors.phi_deg = Prior{0.0, 1.0};
    r.initial_pose = {{}, H_mm, 5.05};
    r.picks = picks;
    r.num_lines = 2;
    return r;
  }
  std::vector<Pick> picks;
  CameraSpec camera;
};

TEST_F(PaperTable1a, YawAndPitchNearZeroLinesOneLensHeightAside) {
  LaneSolver solver(camera, 16);
  for (const double H : {300.0, 1000.0}) {
    const SolveResult& res = solver.solve(request(H));
    ASSERT_TRUE(res.converged) << to_string(res.status);
    EXPECT_FALSE(res.rank_deficient);
    EXPECT_NEAR(rad_to_deg(res.pose.attitude.psi), 0.0, 0.5);
    EXPECT_NEAR(rad_to_deg(res.pose.attitude.theta), 0.0, 0.5);
    const double lens_height = H - camera.yM_mm;
    EXPECT_NEAR(res.lines[0].y0_mm / lens_height, 1.0, 0.05) << "H " << H;
    EXPECT_NEAR(res.lines[1].y0_mm / lens_height, -1.0, 0.05) << "H " << H;
    // Hand picks: a reprojection RMS below a pixel, and roll held by its prior alone.
    EXPECT_LT(res.rms_px, 1.0);
    EXPECT_NEAR(res.sigma.phi_deg, 1.0, 0.01);
  }
  // The paper's own index on the same picks (roll fixed at the gyro's 0) agrees.
  SolveRequest r = request(1000.0);
  r.mode = SolverMode::paper;
  r.free.remove(FreeParam::phi);
  const SolveResult& paper = solver.solve(r);
  ASSERT_TRUE(paper.converged);
  EXPECT_NEAR(rad_to_deg(paper.pose.attitude.psi), 0.0, 0.5);
  EXPECT_NEAR(rad_to_deg(paper.pose.attitude.theta), 0.0, 0.5);
  EXPECT_NEAR(paper.lines[0].y0_mm / (1000.0 - camera.yM_mm), 1.0, 0.05);
}

TEST_F(PaperTable1a, FreeHeightIsReportedUndetermined) {
  LaneSolver solver(camera, 16);
  SolveRequest r = request(1000.0);
  r.free.add(FreeParam::H);
  const SolveResult& res = solver.solve(r);
  EXPECT_TRUE(res.rank_deficient);
  EXPECT_TRUE(std::isnan(res.sigma.H_mm));
}

}  // namespace
}  // namespace ccdlane
