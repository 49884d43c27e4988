// LaneSolver: input checks, the starting point, the LM solve in the requested mode, and
// the result with its uncertainty. All storage is sized in the constructor.
#include "core/solver/lane_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/solver/covariance.hpp"
#include "core/solver/initial_guess.hpp"
#include "core/solver/levenberg_marquardt.hpp"
#include "core/solver/paper_residual.hpp"
#include "core/solver/prior_residuals.hpp"
#include "core/solver/reprojection_residual.hpp"

namespace ccdlane {

using namespace solver;

const char* to_string(SolveStatus s) {
  switch (s) {
    case SolveStatus::converged_cost: return "converged_cost";
    case SolveStatus::converged_step: return "converged_step";
    case SolveStatus::max_iterations: return "max_iterations";
    case SolveStatus::invalid_input: return "invalid_input";
    case SolveStatus::too_few_picks: return "too_few_picks";
    case SolveStatus::no_ground_point: return "no_ground_point";
    case SolveStatus::numerical_failure: return "numerical_failure";
  }
  return "unknown";
}

SolveSigmas::SolveSigmas() {
  y0_mm.fill(kUndetermined);
  m.fill(kUndetermined);
  c_per_mm.fill(kUndetermined);
}

double radius_of_curvature_mm(const RoadLine& line) {
  if (line.c_per_mm == 0.0) return std::numeric_limits<double>::infinity();
  return std::pow(1.0 + line.m * line.m, 1.5) / (2.0 * line.c_per_mm);
}

int required_picks(const SolveRequest& request) {
  const ParameterLayout layout(request.free, request.num_lines, request.line_model);
  const int priors = request.mode == SolverMode::reprojection ? count_free_priors(request.priors, layout) : 0;
  // 2 residuals per pick against 1 unknown per pick: picks + priors >= reduced unknowns.
  return std::max(1, layout.size() - priors);
}

namespace {

constexpr double kWarmInitialDamping = 1e-6;  // see LmOptions

bool finite_prior(const std::optional<Prior>& p) {
  return !p || (std::isfinite(p->mean) && std::isfinite(p->sigma) && p->sigma > 0.0);
}

bool valid_pose(const CameraPose& p) {
  return std::isfinite(p.attitude.psi) && std::isfinite(p.attitude.theta) && std::isfinite(p.attitude.phi) &&
         std::isfinite(p.H_mm) && p.H_mm > 0.0 && std::isfinite(p.f_mm) && p.f_mm > 0.0;
}

double to_interface_units(FreeParam kind, double internal) {
  const bool angle = kind == FreeParam::psi || kind == FreeParam::theta || kind == FreeParam::phi;
  return angle ? rad_to_deg(internal) : internal;
}

}  // namespace

struct LaneSolver::Impl {
  Impl(const CameraSpec& spec, int max_picks_in, int max_lines_in)
      : camera(spec, CameraPose{{}, 1.0, 1.0}),
        max_picks(max_picks_in),
        max_lines(max_lines_in),
        x_a(static_cast<std::size_t>(max_picks)),
        x_b(x_a.size()),
        rows_a(max_picks),
        rows_b(max_picks),
        sorted(x_a.size()),
        order(x_a.size()),
        ground(x_a.size()),
        ideal(x_a.size()),
        points(x_a.size()),
        reprojection(spec, max_picks),
        paper(spec),
        lm(max_picks) {
    state_a.x = x_a.data();
    state_a.rows = &rows_a;
    state_b.x = x_b.data();
    state_b.rows = &rows_b;
  }

  const SolveResult& solve(const SolveRequest& request);
  // The status that rejects `request`, or nothing when it can be solved.
  std::optional<SolveStatus> reject(const SolveRequest& request);
  void finish(const SolveRequest& request, const SolverState& state, const LmOutcome& lm_out);

  CameraModel camera;
  int max_picks;
  int max_lines;
  // Sorts the request's picks by line into `sorted` (order[i]: sorted pick i's index in
  // the request) and sets `segments`: inside the solve every per-line pass is then over
  // one contiguous range.
  void sort_by_line(std::span<const Pick> picks, int num_lines);

  std::vector<double> x_a, x_b;
  PickRows rows_a, rows_b;
  std::vector<Pick> sorted;
  std::vector<int> order;
  LineSegments segments;
  std::vector<Vec2> ground, ideal, points;
  SolverState state_a, state_b;
  ReprojectionResidual reprojection;
  PaperResidual paper;
  LmWorkspace lm;
  CovarianceWorkspace cov;
  ParameterLayout layout;
  SolveResult result;
};

std::optional<SolveStatus> LaneSolver::Impl::reject(const SolveRequest& r) {
  if (r.num_lines < 1 || r.num_lines > max_lines) return SolveStatus::invalid_input;
  // Nothing free leaves no problem to solve (and no reduced system to build); a shared
  // curvature is the lines' only c, so a c per line as well is a contradiction.
  const bool shared_c = r.line_model == LineModel::shared_curvature;
  if (shared_c && r.free.has(FreeParam::c)) return SolveStatus::invalid_input;
  if (ParameterLayout(r.free, r.num_lines, r.line_model).size() == 0) return SolveStatus::invalid_input;
  if (r.picks.size() > static_cast<std::size_t>(max_picks)) return SolveStatus::invalid_input;
  if (!(std::isfinite(r.pixel_sigma) && r.pixel_sigma > 0.0) || r.max_iterations < 1) return SolveStatus::invalid_input;
  if (!valid_pose(r.initial_pose)) return SolveStatus::invalid_input;
  const SolverPriors& p = r.priors;
  for (const auto* prior : {&p.psi_deg, &p.theta_deg, &p.phi_deg, &p.H_mm, &p.f_mm, &p.lane_width_mm})
    if (!finite_prior(*prior)) return SolveStatus::invalid_input;
  if (!r.initial_lines.empty()) {
    if (r.initial_lines.size() != static_cast<std::size_t>(r.num_lines)) return SolveStatus::invalid_input;
    for (const RoadLine& l : r.initial_lines)
      if (!std::isfinite(l.y0_mm) || !std::isfinite(l.m) || !std::isfinite(l.c_per_mm))
        return SolveStatus::invalid_input;
  }
  for (std::size_t i = 0; i < r.picks.size(); ++i) {
    const Pick& pick = r.picks[i];
    if (pick.line < 0 || pick.line >= r.num_lines || !std::isfinite(pick.px) || !std::isfinite(pick.py)) {
      result.failed_pick = static_cast<int>(i);
      return SolveStatus::invalid_input;
    }
  }
  if (static_cast<int>(r.picks.size()) < required_picks(r)) return SolveStatus::too_few_picks;
  return std::nullopt;
}

void LaneSolver::Impl::sort_by_line(std::span<const Pick> picks, int num_lines) {
  segments.begin.fill(0);
  for (const Pick& p : picks) ++segments.begin[p.line + 1];
  for (int j = 0; j < num_lines; ++j) segments.begin[j + 1] += segments.begin[j];
  std::array<int, kMaxLaneLines> next{};
  std::copy_n(segments.begin.begin(), kMaxLaneLines, next.begin());
  for (std::size_t i = 0; i < picks.size(); ++i) {
    const int to = next[picks[i].line]++;
    sorted[to] = picks[i];
    order[to] = static_cast<int>(i);
  }
}

const SolveResult& LaneSolver::Impl::solve(const SolveRequest& r) {
  result.failed_pick = -1;
  result.iterations = 0;
  result.converged = false;
  result.rank_deficient = false;
  result.cost = 0.0;
  result.rms_px = std::numeric_limits<double>::quiet_NaN();
  result.sigma = SolveSigmas{};
  result.points_mm = {};
  result.num_free = 0;
  result.covariance.resize(0, 0);
  result.pose = r.initial_pose;
  result.num_lines = 0;

  if (const std::optional<SolveStatus> s = reject(r)) {
    result.status = *s;
    return result;
  }
  sort_by_line(r.picks, r.num_lines);
  const std::span<const Pick> picks(sorted.data(), r.picks.size());
  const int num_picks = static_cast<int>(picks.size());
  layout = ParameterLayout(r.free, r.num_lines, r.line_model);

  if (const int miss = ground_points_of_picks(camera.spec(), r.initial_pose, picks, ground.data()); miss >= 0) {
    result.failed_pick = order[miss];
    result.status = SolveStatus::no_ground_point;
    return result;
  }
  SolverState* current = &state_a;
  SolverState* candidate = &state_b;
  current->pose = r.initial_pose;
  if (r.initial_lines.empty())
    fit_initial_lines(picks, ground.data(), r.num_lines, r.free.has(FreeParam::m), current->lines.data());
  else
    std::copy(r.initial_lines.begin(), r.initial_lines.end(), current->lines.begin());
  if (layout.shared_curvature_index() >= 0) {  // one c for all: start from their mean
    double sum = 0.0;
    for (int j = 0; j < r.num_lines; ++j) sum += current->lines[j].c_per_mm;
    for (int j = 0; j < r.num_lines; ++j) current->lines[j].c_per_mm = sum / r.num_lines;
  }
  for (std::size_t i = 0; i < picks.size(); ++i) current->x[i] = ground[i].x();

  const bool warm = r.warm_start;
  LmOptions options{r.max_iterations, kWarmInitialDamping};
  bool evaluated = false;
  LmOutcome outcome;
  if (r.mode == SolverMode::paper) {
    camera.set_pose(r.initial_pose);
    for (std::size_t i = 0; i < picks.size(); ++i)
      ideal[i] = *camera.ideal_from_observed(Vec2(picks[i].px, picks[i].py));  // exists: ground point did
    paper.configure(layout, picks, std::span<const Vec2>(ideal.data(), picks.size()));
    evaluated = paper.evaluate(*current) && linearise(paper, layout, segments, *current);
    if (!warm) options.initial_damping = PaperResidual::kColdInitialDamping;
    if (evaluated) outcome = levenberg_marquardt(paper, layout, segments, num_picks, options, current, candidate, lm);
  } else {
    reprojection.configure(layout, segments, picks, r.pixel_sigma, r.priors);
    evaluated = reprojection.evaluate_cost(*current) && linearise(reprojection, layout, segments, *current);
    if (!warm) options.initial_damping = ReprojectionResidual::kColdInitialDamping;
    if (evaluated)
      outcome = levenberg_marquardt(reprojection, layout, segments, num_picks, options, current, candidate, lm);
  }
  if (!evaluated || !std::isfinite(current->cost)) outcome.status = SolveStatus::numerical_failure;
  finish(r, *current, outcome);
  return result;
}

void LaneSolver::Impl::finish(const SolveRequest& r, const SolverState& state, const LmOutcome& outcome) {
  const std::span<const Pick> picks(sorted.data(), r.picks.size());
  result.status = outcome.status;
  result.converged = outcome.status == SolveStatus::converged_cost || outcome.status == SolveStatus::converged_step;
  result.iterations = outcome.iterations;
  result.cost = state.cost;
  result.pose = state.pose;
  result.num_lines = r.num_lines;
  result.lines = state.lines;

  // Mark positions and the reprojection RMS: from the whitened residuals in
  // reprojection mode; the paper's index is not in pixels, so there the marks are
  // projected.
  const int num_picks = static_cast<int>(picks.size());
  for (int i = 0; i < num_picks; ++i) {
    const double x = state.x[i];
    points[order[i]] = Vec2(x, line_y(state.lines[picks[i].line], x));  // in the request's order
  }
  double sum_sq = 0.0;
  if (r.mode == SolverMode::reprojection) {
    const PickRows& rows = *state.rows;
    sum_sq =
        (rows.r0.head(num_picks).square() + rows.r1.head(num_picks).square()).sum() * r.pixel_sigma * r.pixel_sigma;
  } else {
    camera.set_pose(state.pose);
    for (int i = 0; i < num_picks; ++i) {
      const Vec2& point = points[order[i]];
      const auto px = camera.pixel_from_point(Vec3(point.x(), point.y(), 0.0));
      sum_sq += px ? (*px - Vec2(picks[i].px, picks[i].py)).squaredNorm() : std::numeric_limits<double>::infinity();
    }
  }
  result.points_mm = std::span<const Vec2>(points.data(), picks.size());
  result.rms_px = picks.empty() ? 0.0 : std::sqrt(sum_sq / static_cast<double>(picks.size()));
  if (outcome.status == SolveStatus::numerical_failure) return;

  // Uncertainty from the undamped reduced normal matrix at the optimum.
  const int n = layout.size();
  build_reduced_system(layout, state, 0.0, lm.N, lm.g);
  double variance_scale = 1.0;
  if (r.mode == SolverMode::paper) {
    const int spare = static_cast<int>(picks.size()) - n;
    variance_scale = spare > 0 ? state.cost / spare : std::numeric_limits<double>::quiet_NaN();
  }
  const CovarianceAnalysis analysis = analyse_covariance(lm.N, variance_scale, cov, result.covariance);
  result.rank_deficient = analysis.rank_deficient;
  result.num_free = n;
  for (int k = 0; k < n; ++k) {
    const ReducedParam p = layout.describe(k);
    result.free_params[k] = p;
    const double sigma = to_interface_units(p.kind, std::sqrt(result.covariance(k, k)));
    switch (p.kind) {
      case FreeParam::psi: result.sigma.psi_deg = sigma; break;
      case FreeParam::theta: result.sigma.theta_deg = sigma; break;
      case FreeParam::phi: result.sigma.phi_deg = sigma; break;
      case FreeParam::H: result.sigma.H_mm = sigma; break;
      case FreeParam::f: result.sigma.f_mm = sigma; break;
      case FreeParam::y0: result.sigma.y0_mm[p.line] = sigma; break;
      case FreeParam::m: result.sigma.m[p.line] = sigma; break;
      case FreeParam::c:
        if (p.line >= 0)
          result.sigma.c_per_mm[p.line] = sigma;
        else
          std::fill_n(result.sigma.c_per_mm.begin(), r.num_lines, sigma);  // shared
        break;
    }
  }
}

LaneSolver::LaneSolver(const CameraSpec& camera, int max_picks, int max_lines) {
  if (max_picks < 1) throw std::invalid_argument("LaneSolver: max_picks must be at least 1");
  if (max_lines < 1 || max_lines > kMaxLaneLines)
    throw std::invalid_argument("LaneSolver: max_lines must be 1.." + std::to_string(kMaxLaneLines));
  impl_ = std::make_unique<Impl>(camera, max_picks, max_lines);
}

LaneSolver::~LaneSolver() = default;

const SolveResult& LaneSolver::solve(const SolveRequest& request) { return impl_->solve(request); }
int LaneSolver::max_picks() const { return impl_->max_picks; }
int LaneSolver::max_lines() const { return impl_->max_lines; }

}  // namespace ccdlane
