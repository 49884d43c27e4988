// The chessboard projection: a pinhole onto the chip's cells, then the division model.
//
// With v = (f/pitch_u * x/z, f/pitch_v * y/z) the ideal offset from the principal point,
// the observed pixel is c + g(k, |v|^2) v (distortion.cpp's gain), so the principal
// point enters only additively: d observed / d c = I.
#include "core/calibration/board_projection.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/geometry/distortion.hpp"

namespace ccdlane::calibration {
namespace {

Mat3 skew(const Vec3& v) {
  Mat3 s;
  s << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return s;
}

}  // namespace

std::vector<Vec3> board_corners(const BoardGeometry& board) {
  std::vector<Vec3> corners;
  corners.reserve(static_cast<std::size_t>(board.corner_count()));
  for (int r = 0; r < board.rows; ++r)
    for (int c = 0; c < board.columns; ++c) corners.emplace_back(c * board.square_mm, r * board.square_mm, 0.0);
  return corners;
}

std::optional<Vec2> observed_pixel_of_board_point(const CameraSpec& chip, const Intrinsics& in, const BoardPose& pose,
                                                  const Vec3& point, IntrinsicsJacobian* d_intrinsics,
                                                  BoardPoseJacobian* d_pose) {
  const Vec3 turned = pose.rotation * point;
  const Vec3 p = turned + pose.translation_mm;
  if (!(p.z() > 0.0)) return std::nullopt;
  const double su = in.f_mm / chip.pitch_u(), sv = in.f_mm / chip.pitch_v();
  const double inv_z = 1.0 / p.z();
  const Vec2 v(su * p.x() * inv_z, sv * p.y() * inv_z);
  const Vec2 centre(in.cx, in.cy);
  Mat2 d_obs_d_v;
  const auto observed = distort_pixel(centre + v, centre, in.k_px2, &d_obs_d_v);
  if (!observed) return std::nullopt;
  if (d_intrinsics) {
    const double rho = v.squaredNorm();
    const double s = std::sqrt(1.0 - 4.0 * in.k_px2 * rho);
    const double dgain_dk = 4.0 * rho / (s * (1.0 + s) * (1.0 + s));
    d_intrinsics->col(0) = d_obs_d_v * (v / in.f_mm);
    d_intrinsics->col(1) = Vec2::UnitX();
    d_intrinsics->col(2) = Vec2::UnitY();
    d_intrinsics->col(3) = dgain_dk * v;
  }
  if (d_pose) {
    Eigen::Matrix<double, 2, 3> dv_dp;
    dv_dp << su * inv_z, 0.0, -su * p.x() * inv_z * inv_z, 0.0, sv * inv_z, -sv * p.y() * inv_z * inv_z;
    const Eigen::Matrix<double, 2, 3> d_obs_d_p = d_obs_d_v * dv_dp;
    // exp([w]x) R X ~ R X + w x (R X): d p / d w = -[R X]x.
    d_pose->leftCols<3>() = -d_obs_d_p * skew(turned);
    d_pose->rightCols<3>() = d_obs_d_p;
  }
  return observed;
}

Mat3 rotation_from_vector(const Vec3& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Mat3::Identity() + skew(w);
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

BoardPose apply_pose_step(const BoardPose& pose, const Eigen::Matrix<double, kPoseCount, 1>& step) {
  return {rotation_from_vector(step.head<3>()) * pose.rotation, pose.translation_mm + step.tail<3>()};
}

double board_tilt_deg(const BoardPose& pose) {
  // The board normal is the rotation's third column; the axis is z.
  return rad_to_deg(std::acos(std::min(1.0, std::abs(pose.rotation(2, 2)))));
}

}  // namespace ccdlane::calibration
