// Camera intrinsics from chessboard views: f, principal point and division-model k fitted
// by Levenberg-Marquardt with the chip geometry fixed and every board pose free.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/calibration/board_projection.hpp"

namespace ccdlane::calibration {

// One picture's found corners, in board_corners' order, as 1-based observed pixels.
struct BoardView {
  int width = 0;  // picture size in pixels
  int height = 0;
  std::vector<Vec2> corners_px;
};

enum class CalibrationStatus {
  ok,
  too_few_views,       // fewer than kMinViews pictures with the board found
  mixed_sizes,         // pictures of different sizes (failed_view names the first odd one)
  wrong_size,          // pictures that are not the chip's Nu x Nv
  wrong_corner_count,  // a view without exactly the board's corners (a caller's bug)
  not_determined,      // the views do not fix f (all boards nearly facing the camera)
  no_convergence,      // the fit could not be completed (numerical failure)
};

struct CalibrationOptions {
  int max_iterations = 100;
  // Refuse f when the boards' largest tilt from facing the camera is below this, or when
  // f's sigma exceeds this fraction of f: either way the pictures hold too little
  // perspective to tell a focal length from a distance.
  double min_tilt_deg = 3.0;
  double max_relative_f_sigma = 0.02;
};

struct ViewResidual {
  double rms_px = 0.0;
  double tilt_deg = 0.0;  // board normal from the optical axis
  BoardPose pose;
  std::vector<Vec2> reprojected_px;  // the model's corners, board_corners' order
};

struct CameraCalibration {
  CalibrationStatus status = CalibrationStatus::no_convergence;
  std::string message;   // why, for anything but ok
  int failed_view = -1;  // the view a size refusal is about
  Intrinsics intrinsics;
  Intrinsics sigma;                                      // from the covariance scaled by the residual variance
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // f_mm, cx, cy, k_px2
  double rms_px = 0.0;             // sqrt(mean |observed - model|^2) over the corners, as OpenCV reports it
  double residual_sigma_px = 0.0;  // sqrt(sum r^2 / (equations - unknowns))
  int iterations = 0;
  std::vector<ViewResidual> views;
};

constexpr int kMinViews = 3;

// `chip` gives the cell pitch and the picture size (Nu x Nv); its principal point and k
// are not used (the fit starts from the picture's centre and k = 0). `initial_f_mm` is
// where it starts when the homographies give no focal length of their own. Every view
// must hold board.corner_count() corners.
CameraCalibration calibrate_camera(const CameraSpec& chip, double initial_f_mm, const BoardGeometry& board,
                                   const std::vector<BoardView>& views, const CalibrationOptions& options = {});

const char* to_string(CalibrationStatus status);

}  // namespace ccdlane::calibration
