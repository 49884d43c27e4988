// Pixel -> road in a few multiply-adds, for loops over many pixels (detection's marks,
// the renderer's every pixel) at one pose. The same formulas as
// CameraModel::ground_point_from_pixel (geometry.md "From pixel to road"), rearranged:
// with the undistorted pixel's chip coordinates (a, b), the cell-minus-lens vector is
// q = -f T2 + a T0 + b T1 (T's columns), and the ray meets the road at L - (L_z / q_z) q.
#pragma once

#include "core/geometry/attitude.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane {

class GroundProjector {
 public:
  GroundProjector() = default;
  GroundProjector(const CameraSpec& spec, const CameraPose& pose) { set(spec, pose); }

  void set(const CameraSpec& spec, const CameraPose& pose) {
    const Mat3 T = attitude_matrix(pose.attitude);
    t0_ = T.col(0);
    t1_ = T.col(1);
    t2_ = T.col(2);
    lens_ = CameraModel(spec, pose).lens_centre();
    cx_ = spec.cx;
    cy_ = spec.cy;
    k_ = spec.k_px2;
    pu_ = spec.pitch_u();
    pv_ = spec.pitch_v();
    f_ = pose.f_mm;
  }

  // The cell-minus-lens vector of an observed 1-based pixel; its ray reaches the road
  // only when q.z() > 0. `undistort_scale` (if given) receives 1 / (1 + k r^2).
  Vec3 ray(double px, double py, double* undistort_scale = nullptr) const {
    const double dx = px - cx_, dy = py - cy_;
    const double den = 1.0 + k_ * (dx * dx + dy * dy);
    const double s = den > 0.0 ? 1.0 / den : 0.0;  // no ideal point: a ray along the axis, never ground
    if (undistort_scale) *undistort_scale = s;
    return (dx * s * pu_) * t0_ + (dy * s * pv_) * t1_ - f_ * t2_;
  }

  // Where an observed pixel's ray meets the road; false at or above the horizon.
  bool ground(double px, double py, double& X, double& Y) const {
    const Vec3 q = ray(px, py);
    if (!(q.z() > 0.0)) return false;
    const double t = lens_.z() / q.z();
    X = lens_.x() - t * q.x();
    Y = lens_.y() - t * q.y();
    return true;
  }

  // The ideal (undistorted) pixel of the vanishing point of road direction (1, m, 0);
  // false when that direction points behind the camera.
  bool vanishing_point(double m, double& px, double& py) const {
    const Vec3 d(t0_.x() + m * t0_.y(), t1_.x() + m * t1_.y(), t2_.x() + m * t2_.y());  // T^T (1, m, 0)
    if (!(d.z() > 0.0)) return false;
    px = cx_ - f_ * d.x() / (d.z() * pu_);
    py = cy_ - f_ * d.y() / (d.z() * pv_);
    return true;
  }

  const Vec3& lens() const { return lens_; }
  const Vec3& t0() const { return t0_; }
  const Vec3& t1() const { return t1_; }
  const Vec3& t2() const { return t2_; }
  double pitch_u() const { return pu_; }
  double pitch_v() const { return pv_; }

 private:
  Vec3 t0_ = Vec3::UnitX(), t1_ = Vec3::UnitY(), t2_ = Vec3::UnitZ(), lens_ = Vec3::Zero();
  double cx_ = 0, cy_ = 0, k_ = 0, pu_ = 1, pv_ = 1, f_ = 1;
};

}  // namespace ccdlane
