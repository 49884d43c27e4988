// Pixel -> road in a few multiply-adds, for loops over many pixels (detection's marks,
// the renderer's every pixel) at one pose. The same formulas as
// CameraModel::ground_point_from_pixel (docs/geometry.md "From pixel to road"), rearranged:
// with the undistorted pixel's chip coordinates (a, b), the cell-minus-lens vector is
// q = -f T2 + a T0 + b T1 (T's columns), and the ray meets the road at L - (L_z / q_z) q.
#pragma once

#include "core/geometry/attitude.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane {

// A fixed-frame vector as three plain doubles: these loops also run in unoptimised
// (sanitizer) builds, where Eigen's expression templates cost ten times as much.
struct Ray {
  double x = 0, y = 0, z = 0;
};

class GroundProjector {
 public:
  GroundProjector() = default;
  GroundProjector(const CameraSpec& spec, const CameraPose& pose) { set(spec, pose); }

  void set(const CameraSpec& spec, const CameraPose& pose) {
    const Mat3 T = attitude_matrix(pose.attitude);
    t0_ = {T(0, 0), T(1, 0), T(2, 0)};
    t1_ = {T(0, 1), T(1, 1), T(2, 1)};
    t2_ = {T(0, 2), T(1, 2), T(2, 2)};
    const Vec3 L = CameraModel(spec, pose).lens_centre();
    lens_ = {L.x(), L.y(), L.z()};
    cx_ = spec.cx;
    cy_ = spec.cy;
    k_ = spec.k_px2;
    pu_ = spec.pitch_u();
    pv_ = spec.pitch_v();
    f_ = pose.f_mm;
  }

  // The cell-minus-lens vector of an observed 1-based pixel; its ray reaches the road
  // only when z > 0. `undistort_scale` (if given) receives 1 / (1 + k r^2).
  Ray ray(double px, double py, double* undistort_scale = nullptr) const {
    const double dx = px - cx_, dy = py - cy_;
    const double den = 1.0 + k_ * (dx * dx + dy * dy);
    const double s = den > 0.0 ? 1.0 / den : 0.0;  // no ideal point: a ray along the axis, never ground
    if (undistort_scale) *undistort_scale = s;
    const double a = dx * s * pu_, b = dy * s * pv_;
    return {a * t0_.x + b * t1_.x - f_ * t2_.x, a * t0_.y + b * t1_.y - f_ * t2_.y, a * t0_.z + b * t1_.z - f_ * t2_.z};
  }

  // Where an observed pixel's ray meets the road; false at or above the horizon.
  bool ground(double px, double py, double& X, double& Y) const {
    const Ray q = ray(px, py);
    if (!(q.z > 0.0)) return false;
    const double t = lens_.z / q.z;
    X = lens_.x - t * q.x;
    Y = lens_.y - t * q.y;
    return true;
  }

  // The ideal (undistorted) pixel of the vanishing point of road direction (1, m, 0);
  // false when that direction points behind the camera.
  bool vanishing_point(double m, double& px, double& py) const {
    // d = T^T (1, m, 0): the direction in film components.
    const double dx = t0_.x + m * t0_.y, dy = t1_.x + m * t1_.y, dz = t2_.x + m * t2_.y;
    if (!(dz > 0.0)) return false;
    px = cx_ - f_ * dx / (dz * pu_);
    py = cy_ - f_ * dy / (dz * pv_);
    return true;
  }

  const Ray& lens() const { return lens_; }
  const Ray& t0() const { return t0_; }  // T's columns
  const Ray& t1() const { return t1_; }
  const Ray& t2() const { return t2_; }
  double pitch_u() const { return pu_; }
  double pitch_v() const { return pv_; }

 private:
  Ray t0_{1, 0, 0}, t1_{0, 1, 0}, t2_{0, 0, 1}, lens_{};
  double cx_ = 0, cy_ = 0, k_ = 0, pu_ = 1, pv_ = 1, f_ = 1;
};

}  // namespace ccdlane
