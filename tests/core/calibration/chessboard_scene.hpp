// Synthetic chessboard views with known truth: corner pixels and rendered pictures.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/calibration/board_projection.hpp"
#include "core/geometry/camera_spec.hpp"

namespace ccdlane::test {

// A 640x480 camera on a 4 um cell with an off-centre principal point and barrel
// distortion (k f^2 = -0.22 in normalised terms, a common wide lens).
struct ChessboardCamera {
  CameraSpec chip;  // its cx, cy, k_px2 are the truth too
  calibration::Intrinsics truth;
};
ChessboardCamera chessboard_camera();

// Poses of the board that keep every corner (and one square of margin) in the picture:
// tilted 15-45 degrees about a random axis in the picture plane, turned up to 25 degrees
// in the board's plane, 400-650 mm away. max_tilt_deg caps the tilt (0: facing the camera).
std::vector<calibration::BoardPose> varied_board_poses(const ChessboardCamera& camera,
                                                       const calibration::BoardGeometry& board, int count,
                                                       std::mt19937& rng, double min_tilt_deg = 15.0,
                                                       double max_tilt_deg = 45.0);

// The corners' observed pixels through docs/geometry.md's pinhole and division model, written
// out here (not through board_projection) so the fit is checked against an independent
// path. Gaussian noise of sigma_px per coordinate when sigma_px > 0.
std::vector<Vec2> corner_pixels(const ChessboardCamera& camera, const calibration::BoardGeometry& board,
                                const calibration::BoardPose& pose, double sigma_px, std::mt19937& rng);

// The board rendered into an 8-bit grey picture (Nu x Nv, row-major): black and white
// squares with a one-square white margin on a grey background, each pixel the mean of
// 4x4 samples over its area (so edges are antialiased as a lens and a sensor would), plus
// Gaussian pixel noise of noise_grey levels.
std::vector<std::uint8_t> render_board(const ChessboardCamera& camera, const calibration::BoardGeometry& board,
                                       const calibration::BoardPose& pose, double noise_grey, std::mt19937& rng);

}  // namespace ccdlane::test
