// A starting point for the chessboard fit: plane homographies, Zhang's focal length, poses.
#pragma once

#include <optional>
#include <span>

#include "core/calibration/board_projection.hpp"

namespace ccdlane::calibration {

// The homography taking board (x, y, 1) to chip millimetres about the principal point,
// ((Px - cx) pitch_u, (Py - cy) pitch_v, 1), fitted by normalised DLT (Hartley) to the
// corners as if there were no distortion. Empty for fewer than 4 corners or a degenerate fit.
std::optional<Mat3> board_to_chip_homography(const CameraSpec& chip, double cx, double cy, std::span<const Vec3> board,
                                             std::span<const Vec2> corners_px);

// Zhang's closed form ("A flexible new technique for camera calibration", 2000) reduced
// to the one unknown this model has: with the principal point assumed and square chip
// coordinates, each homography gives two equations linear in 1/f^2, solved together by
// least squares. Empty when they do not give a positive 1/f^2: views (nearly) facing the
// camera carry no perspective and hence no focal length.
std::optional<double> focal_length_from_homographies(std::span<const Mat3> homographies);

// The board pose for a homography and a focal length: [r1 r2 t] = K^-1 H up to scale,
// then the nearest rotation (SVD), with the board in front of the camera.
BoardPose pose_from_homography(const Mat3& homography, double f_mm);

}  // namespace ccdlane::calibration
