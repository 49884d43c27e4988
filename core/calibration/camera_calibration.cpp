// The chessboard fit: a small dense Levenberg-Marquardt over 4 intrinsics + 6 per view.
//
// Why not the project's LM template (core/solver/levenberg_marquardt.hpp): it is built
// around the lane problem's layout (ParameterLayout, per-pick x_i eliminated by a Schur
// complement, preallocated SolverState) for the per-frame path. This problem has another
// structure (a 6-parameter block per view) and runs once in a tool, where a few hundred
// unknowns fit in a dense normal matrix and allocation does not matter. The loop follows
// the same rules: Marquardt's scale-invariant damping (here by Jacobi scaling, which also
// keeps the f / k columns, 1e8 apart in raw units, well conditioned) and Nielsen's update.
#include "core/calibration/camera_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/calibration/homography_initialisation.hpp"
#include "core/solver/nielsen_damping.hpp"

namespace ccdlane::calibration {
namespace {

struct FitState {
  Intrinsics intrinsics;
  std::vector<BoardPose> poses;
};

class ChessboardProblem {
 public:
  ChessboardProblem(const CameraSpec& chip, const std::vector<Vec3>& board, const std::vector<BoardView>& views)
      : chip_(chip), board_(board), views_(views) {}

  int unknowns() const { return kIntrinsicCount + kPoseCount * static_cast<int>(views_.size()); }
  int equations() const { return 2 * static_cast<int>(board_.size() * views_.size()); }

  // Residuals model - observed, and their Jacobian when asked. False when a corner falls
  // behind the lens or beyond the distortion's field.
  bool evaluate(const FitState& s, Eigen::VectorXd& r, Eigen::MatrixXd* jacobian) const {
    r.resize(equations());
    if (jacobian) jacobian->setZero(equations(), unknowns());
    IntrinsicsJacobian d_in;
    BoardPoseJacobian d_pose;
    Eigen::Index row = 0;
    for (std::size_t v = 0; v < views_.size(); ++v) {
      for (std::size_t i = 0; i < board_.size(); ++i, row += 2) {
        const auto model = observed_pixel_of_board_point(chip_, s.intrinsics, s.poses[v], board_[i],
                                                         jacobian ? &d_in : nullptr, jacobian ? &d_pose : nullptr);
        if (!model) return false;
        r.segment<2>(row) = *model - views_[v].corners_px[i];
        if (jacobian) {
          jacobian->block<2, kIntrinsicCount>(row, 0) = d_in;
          jacobian->block<2, kPoseCount>(row, kIntrinsicCount + kPoseCount * static_cast<Eigen::Index>(v)) = d_pose;
        }
      }
    }
    return true;
  }

  FitState stepped(const FitState& s, const Eigen::VectorXd& step) const {
    FitState out = s;
    out.intrinsics.f_mm += step(0);
    out.intrinsics.cx += step(1);
    out.intrinsics.cy += step(2);
    out.intrinsics.k_px2 += step(3);
    for (std::size_t v = 0; v < s.poses.size(); ++v)
      out.poses[v] = apply_pose_step(
          s.poses[v], step.segment<kPoseCount>(kIntrinsicCount + kPoseCount * static_cast<Eigen::Index>(v)));
    return out;
  }

 private:
  const CameraSpec& chip_;
  const std::vector<Vec3>& board_;
  const std::vector<BoardView>& views_;
};

// Jacobi scaling: columns of unit norm, so that damping, stopping and the covariance's
// inverse all work on a matrix of unit diagonal.
Eigen::VectorXd column_scales(const Eigen::MatrixXd& normal) {
  Eigen::VectorXd d(normal.rows());
  for (Eigen::Index c = 0; c < normal.rows(); ++c) d(c) = normal(c, c) > 0.0 ? 1.0 / std::sqrt(normal(c, c)) : 1.0;
  return d;
}

struct LmResult {
  bool ok = false;
  int iterations = 0;
};

LmResult levenberg_marquardt(const ChessboardProblem& problem, FitState& state, int max_iterations) {
  LmResult out;
  Eigen::VectorXd r, r_new;
  Eigen::MatrixXd j;
  if (!problem.evaluate(state, r, &j)) return out;
  double cost = 0.5 * r.squaredNorm();
  solver::NielsenDamping damping;
  double& lambda = damping.lambda;
  Eigen::MatrixXd normal = j.transpose() * j;
  Eigen::VectorXd gradient = j.transpose() * r;
  while (out.iterations < max_iterations) {
    ++out.iterations;
    const Eigen::VectorXd d = column_scales(normal);
    Eigen::MatrixXd a = d.asDiagonal() * normal * d.asDiagonal();
    a.diagonal().array() += lambda;
    const Eigen::VectorXd scaled_step = a.ldlt().solve(-(d.asDiagonal() * gradient));
    if (!scaled_step.allFinite()) return out;
    const Eigen::VectorXd step = d.asDiagonal() * scaled_step;
    // Converged when the step no longer moves any scaled parameter appreciably.
    if (scaled_step.norm() < 1e-10) {
      out.ok = true;
      return out;
    }
    const FitState candidate = problem.stepped(state, step);
    const double predicted = -(gradient.dot(step) + 0.5 * step.dot(normal * step));
    if (!problem.evaluate(candidate, r_new, nullptr)) {
      damping.reject();
      continue;
    }
    const double new_cost = 0.5 * r_new.squaredNorm();
    const double rho = predicted > 0.0 ? (cost - new_cost) / predicted : -1.0;
    if (rho > 0.0) {
      const bool small = cost - new_cost <= 1e-12 * cost;
      state = candidate;
      if (!problem.evaluate(state, r, &j)) return out;
      cost = 0.5 * r.squaredNorm();
      normal = j.transpose() * j;
      gradient = j.transpose() * r;
      if (small || cost == 0.0) {
        out.ok = true;
        return out;
      }
      damping.accept(rho);
    } else {
      damping.reject();
      if (lambda > 1e20) {  // no step decreases the cost: the start is the optimum
        out.ok = true;
        return out;
      }
    }
  }
  out.ok = true;  // the iteration limit: report what was reached, the sigmas say how good
  return out;
}

CameraCalibration refused(CalibrationStatus status, std::string message, int view = -1) {
  CameraCalibration c;
  c.status = status;
  c.message = std::move(message);
  c.failed_view = view;
  return c;
}

std::string format(double v, int precision = 3) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*f", precision, v);
  return buffer;
}

}  // namespace

const char* to_string(CalibrationStatus status) {
  switch (status) {
    case CalibrationStatus::ok: return "ok";
    case CalibrationStatus::too_few_views: return "too few views";
    case CalibrationStatus::mixed_sizes: return "pictures of different sizes";
    case CalibrationStatus::wrong_size: return "pictures not of the chip's size";
    case CalibrationStatus::wrong_corner_count: return "wrong corner count";
    case CalibrationStatus::not_determined: return "focal length not determined";
    case CalibrationStatus::no_convergence: return "no convergence";
  }
  return "?";
}

namespace {

// Why the views cannot be calibrated from, as the refused calibration; empty when they can.
std::optional<CameraCalibration> unusable_views(const CameraSpec& chip, const std::vector<Vec3>& corners,
                                                const std::vector<BoardView>& views) {
  for (std::size_t v = 0; v < views.size(); ++v)
    if (views[v].corners_px.size() != corners.size())
      return refused(CalibrationStatus::wrong_corner_count,
                     "view " + std::to_string(v) + " has " + std::to_string(views[v].corners_px.size()) +
                         " corners, the board " + std::to_string(corners.size()),
                     static_cast<int>(v));
  if (static_cast<int>(views.size()) < kMinViews)
    return refused(CalibrationStatus::too_few_views, std::to_string(views.size()) + " usable view(s), at least " +
                                                         std::to_string(kMinViews) + " are needed");
  for (std::size_t v = 1; v < views.size(); ++v)
    if (views[v].width != views[0].width || views[v].height != views[0].height)
      return refused(CalibrationStatus::mixed_sizes,
                     "pictures of different sizes: " + std::to_string(views[v].width) + "x" +
                         std::to_string(views[v].height) + ", the first is " + std::to_string(views[0].width) + "x" +
                         std::to_string(views[0].height),
                     static_cast<int>(v));
  if (views[0].width != chip.Nu || views[0].height != chip.Nv)
    return refused(CalibrationStatus::wrong_size,
                   "the pictures are " + std::to_string(views[0].width) + "x" + std::to_string(views[0].height) +
                       ", the chip (Nu x Nv) " + std::to_string(chip.Nu) + "x" + std::to_string(chip.Nv),
                   0);
  return std::nullopt;
}

// The start: the picture's centre, no distortion, Zhang's f, each pose from its
// homography; the refused calibration when a view's corners fit no plane's picture.
std::optional<CameraCalibration> initial_state(const CameraSpec& chip, double initial_f_mm,
                                               const std::vector<Vec3>& corners, const std::vector<BoardView>& views,
                                               FitState& state) {
  state.intrinsics = {initial_f_mm, CameraSpec::default_cx(chip.Nu), CameraSpec::default_cy(chip.Nv), 0.0};
  std::vector<Mat3> homographies;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const auto h =
        board_to_chip_homography(chip, state.intrinsics.cx, state.intrinsics.cy, corners, views[v].corners_px);
    if (!h)
      return refused(CalibrationStatus::no_convergence,
                     "view " + std::to_string(v) + ": its corners do not fit a plane's picture", static_cast<int>(v));
    homographies.push_back(*h);
  }
  if (const auto f = focal_length_from_homographies(homographies)) state.intrinsics.f_mm = *f;
  for (const Mat3& h : homographies) state.poses.push_back(pose_from_homography(h, state.intrinsics.f_mm));
  return std::nullopt;
}

// Each view's pose, tilt and residuals at the fit (`r`: every corner's, view by view).
void add_view_residuals(const Eigen::VectorXd& r, const std::vector<Vec3>& corners, const std::vector<BoardView>& views,
                        const FitState& state, CameraCalibration& c) {
  for (std::size_t v = 0; v < views.size(); ++v) {
    ViewResidual view;
    view.pose = state.poses[v];
    view.tilt_deg = board_tilt_deg(view.pose);
    const auto rows =
        r.segment(static_cast<Eigen::Index>(2 * corners.size() * v), static_cast<Eigen::Index>(2 * corners.size()));
    view.rms_px = std::sqrt(rows.squaredNorm() / static_cast<double>(corners.size()));
    for (std::size_t i = 0; i < corners.size(); ++i)
      view.reprojected_px.push_back(views[v].corners_px[i] + rows.segment<2>(static_cast<Eigen::Index>(2 * i)));
    c.views.push_back(std::move(view));
  }
}

}  // namespace

CameraCalibration calibrate_camera(const CameraSpec& chip, double initial_f_mm, const BoardGeometry& board,
                                   const std::vector<BoardView>& views, const CalibrationOptions& options) {
  const std::vector<Vec3> corners = board_corners(board);
  if (std::optional<CameraCalibration> refusal = unusable_views(chip, corners, views)) return std::move(*refusal);
  FitState state;
  if (std::optional<CameraCalibration> refusal = initial_state(chip, initial_f_mm, corners, views, state))
    return std::move(*refusal);

  const ChessboardProblem problem(chip, corners, views);
  const LmResult lm = levenberg_marquardt(problem, state, options.max_iterations);
  if (!lm.ok) return refused(CalibrationStatus::no_convergence, "the fit failed (a corner left the model's field)");

  CameraCalibration c;
  c.iterations = lm.iterations;
  c.intrinsics = state.intrinsics;
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  problem.evaluate(state, r, &j);
  const double sum_squares = r.squaredNorm();
  c.rms_px = std::sqrt(sum_squares / static_cast<double>(corners.size() * views.size()));
  const int dof = problem.equations() - problem.unknowns();
  c.residual_sigma_px = std::sqrt(sum_squares / dof);
  add_view_residuals(r, corners, views, state, c);

  double largest_tilt = 0.0;
  for (const ViewResidual& v : c.views) largest_tilt = std::max(largest_tilt, v.tilt_deg);
  const std::string advice = ": tilt the board by 20-45 degrees in several pictures, about different axes";
  if (largest_tilt < options.min_tilt_deg) {
    c.status = CalibrationStatus::not_determined;
    c.message = "the views do not determine f: every board faces the camera within " + format(largest_tilt, 1) +
                " degrees" + advice;
    return c;
  }

  // Covariance: s^2 (J'J)^-1, inverted in the scaled space where the diagonal is 1 so a
  // tiny eigenvalue means a direction the pictures do not fix, not a unit mismatch.
  const Eigen::MatrixXd normal = j.transpose() * j;
  const Eigen::VectorXd d = column_scales(normal);
  const Eigen::MatrixXd scaled = d.asDiagonal() * normal * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
  const Eigen::VectorXd& values = eigen.eigenvalues();
  if (!(values(0) > 1e-12 * values(values.size() - 1))) {
    c.status = CalibrationStatus::not_determined;
    c.message = "the views do not determine f (their normal matrix is singular; largest board tilt " +
                format(largest_tilt, 1) + " degrees)" + advice;
    return c;
  }
  const Eigen::MatrixXd inverse =
      eigen.eigenvectors() * values.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose();
  const double s2 = sum_squares / dof;
  c.covariance =
      s2 * (d.head<kIntrinsicCount>().asDiagonal() * inverse.topLeftCorner<kIntrinsicCount, kIntrinsicCount>() *
            d.head<kIntrinsicCount>().asDiagonal());
  c.sigma = {std::sqrt(c.covariance(0, 0)), std::sqrt(c.covariance(1, 1)), std::sqrt(c.covariance(2, 2)),
             std::sqrt(c.covariance(3, 3))};
  if (!(c.sigma.f_mm <= options.max_relative_f_sigma * c.intrinsics.f_mm)) {
    c.status = CalibrationStatus::not_determined;
    c.message = "the views do not determine f: its sigma is " + format(100.0 * c.sigma.f_mm / c.intrinsics.f_mm, 1) +
                " % of it (largest board tilt " + format(largest_tilt, 1) + " degrees)" + advice;
    return c;
  }
  c.status = CalibrationStatus::ok;
  return c;
}

}  // namespace ccdlane::calibration
