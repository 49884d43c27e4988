// Projection of road points (z = 0) with all the derivatives the solver needs, over all
// picks at once: the solver's hot loop. Same model and results as
// CameraModel::pixel_from_point (tested to rounding), arranged for speed: one array per
// quantity (structure of arrays), every step a coefficient-wise Eigen expression over the
// points, which Eigen vectorises (two or four points per instruction) and which leaves
// the points' division and square-root chains independent of each other.
//
// With v = X - H e3 and the lens offset a (film frame, from the mount), a road point is
// seen along d = T^T v - a. Turning the camera by an angle with fixed-frame axis w moves
// d by -T^T (w x v) = (T^T v) x (T^T w) = (d + a) x w_F: one cross product per angle with
// the film-frame axes w_F, instead of a 3x3 product with dT. For T = Rz Ry Rx P the
// fixed-frame axes are e_z (yaw), Rz e_y (pitch) and Rz Ry e_x = T e_z (roll, about the
// optical axis: the film's own z).
#pragma once

#include <Eigen/Core>

#include "core/geometry/camera_model.hpp"

namespace ccdlane::solver {

class RoadProjection {
 public:
  using Array = Eigen::ArrayXd;

  // Room for `max_points` points: every array is allocated here, never later.
  explicit RoadProjection(int max_points);

  // Per-pose constants (geometry.md; only the attitude matrix, not its derivatives).
  void set_camera(const CameraSpec& spec, const CameraPose& pose);

  // Projects the road points (x[i], y[i], 0), i < n. False when some point is not in
  // front of the lens or beyond the distortion model's field (CameraModel's rules).
  bool project(const Array& x, const Array& y, int n);
  // The observed pixels of the last project().
  const Array& u() const { return u_; }
  const Array& v() const { return v_; }

  // The derivatives of the last project()'s pixels (call once before the columns).
  void differentiate(int n);
  // d pixel / d(road x) (axis 0) or d(road y) (axis 1), into (du, dv).
  void road_column(int axis, int n, Array& du, Array& dv) const;
  // d pixel / d(pose parameter p), into (du, dv).
  void pose_column(PoseParam p, int n, Array& du, Array& dv) const;

 private:
  // D w for a direction w constant over the points: D = d pixel / d(d).
  void fixed_direction(const Vec3& w, int n, Array& du, Array& dv) const;

  Mat3 Tt_ = Mat3::Identity();
  Vec3 lens_in_film_ = Vec3::Zero(), lens_seen_ = Vec3::Zero();
  Vec3 axis_[3];
  double su_ = 1.0, sv_ = 1.0, inv_f_ = 1.0, k_ = 0.0;
  Vec2 centre_ = Vec2::Zero();

  // Per point: d (film frame), 1 / d_z, the ideal pixel w (relative to the principal
  // point), the distortion gain g and dg / d|w|^2, the observed pixel (u, v); then
  // D = d pixel / d d (row-major D00..D12), (d pixel / d w) w, and d + a.
  Array dx_, dy_, dz_, iz_, wx_, wy_, gain_, dgain_, u_, v_;
  Array D00_, D01_, D02_, D10_, D11_, D12_, owx_, owy_, seen_x_, seen_y_, seen_z_;
  mutable Array scratch_;
};

}  // namespace ccdlane::solver
