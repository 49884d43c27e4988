// Projection of road points (z = 0) with the derivatives the solver needs, over all
// picks at once: the solver's hot loop. Same model and results as
// CameraModel::pixel_from_point (tested to rounding), arranged for speed: one array per
// quantity (structure of arrays), each step one pass over the points that the compiler
// vectorises (two or four points per instruction), which also leaves the points'
// division and square-root chains independent of each other.
//
// The solver never needs a pixel Jacobian column itself, only its components along two
// per-pick pixel directions (the Schur elimination's b_x and b_u). So the derivatives are
// pulled back: for a pixel-space covector b, R = b^T (d pixel / d d) is a covector on d,
// the point seen from the lens in film components, and any column then costs one dot
// product with a direction that is the same for every point:
//  * moving the road point along a fixed-frame direction e moves d by T^T e: R . T^T e;
//  * turning the camera by an angle with fixed-frame axis w moves d by
//    -T^T (w x v) = (d + a) x w_F (v = X - H e3, a the lens offset, w_F = T^T w), so
//    b^T d pixel / d angle = R . ((d + a) x w_F) = w_F . (R x (d + a)): the "turn"
//    covector R x (d + a), dotted with the angle's film-frame axis.
// Per point that is two 3-vectors per covector instead of a 2x3 matrix times a cross
// product per column.
#pragma once

#include <array>

#include <Eigen/Core>

#include "core/geometry/camera_model.hpp"

namespace ccdlane::solver {

class RoadProjection {
 public:
  using Array = Eigen::ArrayXd;

  // Pixel-space covectors b and b turned a quarter turn, (-b1, b0), seen through the
  // projection per point (see above): film = b^T d pixel / d d and turn = film x (d + a)
  // for b, and the same for b turned ("across").
  struct Covectors {
    explicit Covectors(int max_points);
    std::array<Array, 3> film, turn, film_across, turn_across;
  };

  // A camera of this spec, room for `max_points` points: every array is allocated here,
  // never later.
  RoadProjection(const CameraSpec& spec, int max_points);

  // Per-pose constants (docs/geometry.md; only the attitude matrix, not its derivatives). The
  // angles' trig comes from the previous pose's when they moved little (AttitudeTrig::
  // moved), so a pose's pixels depend on the poses set before it by a few ulp.
  void set_pose(const CameraPose& pose);
  // Starts afresh: the next pose's trig is computed outright. A solve calls this first,
  // so that its results depend on its own input only.
  void forget_pose() { has_trig_ = false; }

  // Projects the road points (x[i], y[i], 0), i < n. False when some point is not in
  // front of the lens or beyond the distortion model's field (CameraModel's rules).
  bool project(const Array& x, const Array& y, int n);
  // The observed pixels of the last project().
  const Array& u() const { return u_; }
  const Array& v() const { return v_; }

  // The derivatives of the last project()'s pixels (call once before the others below),
  // and with them the first column every user needs: scale * d pixel / d(road point)
  // along the road directions (1, slope[i], 0), into (du, dv).
  void differentiate(const Array& slope, double scale, int n, Array& du, Array& dv);
  // The covectors of b = scale (b0[i], b1[i]) and of b turned, in one pass.
  void pull_back(const Array& b0, const Array& b1, double scale, int n, Covectors& out) const;
  // b^T d pixel / d(road x, axis 0, or road y, axis 1) into `along`, the same for b
  // turned into `across`, from b's covectors.
  void road_along(const Covectors& b, int axis, int n, Array& along, Array& across) const;
  // b^T d pixel / d(pose parameter p) into `along`, the same for b turned into `across`.
  void pose_along(const Covectors& b, PoseParam p, int n, Array& along, Array& across) const;

 private:
  AttitudeTrig trig_;
  Attitude trig_angles_;  // the angles of trig_
  bool has_trig_ = false;
  Mat3 Tt_ = Mat3::Identity();
  Vec3 lens_in_film_ = Vec3::Zero(), lens_seen_ = Vec3::Zero();
  Mat3 axes_in_film_ = Mat3::Identity();  // the angles' turning axes w_F (columns)
  CameraSpec spec_;
  double inv_pitch_u_, inv_pitch_v_;
  Vec2 centre_;
  double k_;
  double f_ = 1.0, su_ = 1.0, sv_ = 1.0;  // the pose's focal length, and in pixels

  // Per point: d (film frame), 1 / d_z, the ideal pixel w (relative to the principal
  // point), the distortion gain g and dg / d|w|^2, the observed pixel (u, v); then the
  // symmetric d pixel / d w (oxx, oxy, oyy).
  Array dx_, dy_, dz_, iz_, wx_, wy_, gain_, dgain_, u_, v_, oxx_, oxy_, oyy_;
  Array scratch_;  // project(): 1 where the point is seen, else 0
};

}  // namespace ccdlane::solver
