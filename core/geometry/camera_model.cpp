// CameraModel: docs/geometry.md's formulas, arranged so every derivative is a few products.
//
// Everything hangs off the mounting point at (0, 0, H): a film-frame offset w from it is
// the fixed-frame point H e3 + T (w - (0, yM, zM)). Hence the lens centre is
// L = H e3 + T a with a = (0, -yM, f - zM), and a fixed-frame point X is seen along
// d = T^T (X - L) = T^T (X - H e3) - a, whose derivatives need only T and dT.
#include "core/geometry/camera_model.hpp"

#include "core/geometry/distortion.hpp"

namespace ccdlane {

CameraModel::CameraModel(const CameraSpec& spec, const CameraPose& pose) : spec_(spec) { set_pose(pose); }

void CameraModel::set_pose(const CameraPose& pose) {
  pose_ = pose;
  T_ = ccdlane::attitude_matrix(pose.attitude, &dT_[0], &dT_[1], &dT_[2]);
  lens_in_film_ = lens_in_film(spec_, pose.f_mm);
}

Vec3 CameraModel::chip_origin() const { return Vec3(0.0, 0.0, pose_.H_mm) - T_ * Vec3(0.0, spec_.yM_mm, spec_.zM_mm); }

Vec3 CameraModel::lens_centre(PoseJacobian3* d_pose) const {
  if (d_pose) {
    for (int k = 0; k < 3; ++k) d_pose->col(k) = dT_[k] * lens_in_film_;
    d_pose->col(kHeight) = Vec3::UnitZ();
    d_pose->col(kFocal) = T_.col(2);
  }
  return Vec3(0.0, 0.0, pose_.H_mm) + T_ * lens_in_film_;
}

Vec2 CameraModel::chip_from_pixel(const Vec2& ideal_px) const {
  return {(ideal_px.x() - spec_.cx) * spec_.pitch_u(), (ideal_px.y() - spec_.cy) * spec_.pitch_v()};
}

Vec2 CameraModel::pixel_from_chip(const Vec2& chip_mm) const {
  return {spec_.cx + chip_mm.x() / spec_.pitch_u(), spec_.cy + chip_mm.y() / spec_.pitch_v()};
}

Vec3 CameraModel::cell_centre(const Vec2& ideal_px, PoseJacobian3* d_pose) const {
  const Vec2 chip = chip_from_pixel(ideal_px);
  const Vec3 w(chip.x(), chip.y() - spec_.yM_mm, -spec_.zM_mm);
  if (d_pose) {
    for (int k = 0; k < 3; ++k) d_pose->col(k) = dT_[k] * w;
    d_pose->col(kHeight) = Vec3::UnitZ();
    d_pose->col(kFocal).setZero();
  }
  return Vec3(0.0, 0.0, pose_.H_mm) + T_ * w;
}

std::optional<Vec2> CameraModel::ideal_from_observed(const Vec2& observed_px) const {
  return undistort_pixel(observed_px, principal_point(), spec_.k_px2);
}

std::optional<Vec2> CameraModel::observed_from_ideal(const Vec2& ideal_px, Mat2* d_observed_d_ideal) const {
  return distort_pixel(ideal_px, principal_point(), spec_.k_px2, d_observed_d_ideal);
}

std::optional<Vec2> CameraModel::ideal_pixel_from_point(const Vec3& point_mm, PointJacobian* d_point,
                                                        PoseJacobian2* d_pose) const {
  const Vec3 above_mount = point_mm - Vec3(0.0, 0.0, pose_.H_mm);
  const Vec3 d = T_.transpose() * above_mount - lens_in_film_;
  if (!(d.z() > 0.0)) return std::nullopt;
  const double su = pose_.f_mm / spec_.pitch_u(), sv = pose_.f_mm / spec_.pitch_v();
  const double inv_z = 1.0 / d.z();
  const Vec2 ideal(spec_.cx - su * d.x() * inv_z, spec_.cy - sv * d.y() * inv_z);
  if (d_point || d_pose) {
    // du/dd for u = c - s * (dx, dy) / dz.
    Eigen::Matrix<double, 2, 3> du_dd;
    du_dd << -su * inv_z, 0.0, su * d.x() * inv_z * inv_z, 0.0, -sv * inv_z, sv * d.y() * inv_z * inv_z;
    if (d_point) *d_point = du_dd * T_.transpose();
    if (d_pose) {
      for (int k = 0; k < 3; ++k) d_pose->col(k) = du_dd * (dT_[k].transpose() * above_mount);
      d_pose->col(kHeight) = du_dd * (-T_.row(2).transpose());
      // f moves the lens along the axis (d_z changes) and scales the image.
      d_pose->col(kFocal) =
          du_dd * Vec3(0.0, 0.0, -1.0) + Vec2(-d.x() * inv_z / spec_.pitch_u(), -d.y() * inv_z / spec_.pitch_v());
    }
  }
  return ideal;
}

std::optional<Vec2> CameraModel::pixel_from_point(const Vec3& point_mm, PointJacobian* d_point,
                                                  PoseJacobian2* d_pose) const {
  const auto ideal = ideal_pixel_from_point(point_mm, d_point, d_pose);
  if (!ideal) return std::nullopt;
  Mat2 d_obs;
  const auto observed = observed_from_ideal(*ideal, (d_point || d_pose) ? &d_obs : nullptr);
  if (!observed) return std::nullopt;
  if (d_point) *d_point = d_obs * *d_point;
  if (d_pose) *d_pose = d_obs * *d_pose;
  return observed;
}

std::optional<Vec3> CameraModel::ground_point_from_ideal_pixel(const Vec2& ideal_px) const {
  const Vec3 p = cell_centre(ideal_px);
  const Vec3 l = lens_centre();
  const double dz = p.z() - l.z();
  // The ray runs from the cell through the lens; it reaches the road only if the cell
  // sits above the lens (the ray goes down on the scene side).
  if (!(dz > 0.0)) return std::nullopt;
  return Vec3(l.x() - l.z() * (p.x() - l.x()) / dz, l.y() - l.z() * (p.y() - l.y()) / dz, 0.0);
}

std::optional<Vec3> CameraModel::ground_point_from_pixel(const Vec2& observed_px) const {
  const auto ideal = ideal_from_observed(observed_px);
  if (!ideal) return std::nullopt;
  return ground_point_from_ideal_pixel(*ideal);
}

}  // namespace ccdlane
