// A chessboard corner seen by the camera: board pose and intrinsics -> observed pixel, with Jacobians.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/geometry/camera_spec.hpp"
#include "core/geometry/types.hpp"

namespace ccdlane::calibration {

// The four intrinsics the chessboard fit estimates; the chip geometry (cell pitch) stays
// as the datasheet gives it.
struct Intrinsics {
  double f_mm = 0.0;
  double cx = 0.0;  // principal point, 1-based pixels
  double cy = 0.0;
  double k_px2 = 0.0;  // division-model distortion (docs/geometry.md)
};
constexpr int kIntrinsicCount = 4;  // f_mm, cx, cy, k_px2, in this order in every Jacobian

// Board -> camera: p = rotation * X + translation, in the camera frame of the pinhole
// picture (x to the right of the picture, y down it, z along the axis toward the scene).
// That frame is docs/geometry.md's film frame turned half a turn about its axis, with the
// origin at the lens centre: docs/geometry.md's d = (-p.x, -p.y, p.z), so its projection
// Px = cx - f d_x / (d_z pitch_u) reads Px = cx + f p_x / (p_z pitch_u) here.
struct BoardPose {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation_mm = Vec3::Zero();
};
constexpr int kPoseCount = 6;  // d rotation (a small turn about the camera axes, rad), d translation (mm)

// The inner corners of a columns x rows board of squares square_mm wide, row by row
// (columns along board x), z = 0: the order in which OpenCV's chessboard finder lists them.
struct BoardGeometry {
  int columns = 0;
  int rows = 0;
  double square_mm = 1.0;
  int corner_count() const { return columns * rows; }
};
std::vector<Vec3> board_corners(const BoardGeometry& board);

using IntrinsicsJacobian = Eigen::Matrix<double, 2, kIntrinsicCount>;
using BoardPoseJacobian = Eigen::Matrix<double, 2, kPoseCount>;

// The observed (distorted) pixel of board point `point` (board frame, mm). Empty when the
// point is not in front of the lens or beyond the distortion's edge of the field. The pose
// Jacobian is with respect to the left-multiplied turn exp([w]x) * rotation and the
// translation, the increments apply_pose_step uses.
std::optional<Vec2> observed_pixel_of_board_point(const CameraSpec& chip, const Intrinsics& intrinsics,
                                                  const BoardPose& pose, const Vec3& point,
                                                  IntrinsicsJacobian* d_intrinsics = nullptr,
                                                  BoardPoseJacobian* d_pose = nullptr);

// The pose moved by a 6-vector step (turn w in rad, then translation in mm).
BoardPose apply_pose_step(const BoardPose& pose, const Eigen::Matrix<double, kPoseCount, 1>& step);

// exp([w]x), Rodrigues' formula, exact also for tiny angles.
Mat3 rotation_from_vector(const Vec3& w);

// The angle between the board's normal and the optical axis, in degrees (0 = facing the camera).
double board_tilt_deg(const BoardPose& pose);

}  // namespace ccdlane::calibration
