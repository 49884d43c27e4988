// Projection of road points (z = 0) with all the derivatives the solver needs, fused
// into one short straight-line kernel: the solver's hot loop. Same model and results as
// CameraModel::pixel_from_point (tested to rounding), arranged for speed.
//
// With v = X - H e3 and the lens offset a (film frame, from the mount), a road point is
// seen along d = T^T v - a. Turning the camera by an angle with fixed-frame axis w moves
// d by -T^T (w x v) = (T^T v) x (T^T w) = (d + a) x w_F: one cross product per angle with
// the film-frame axes w_F, instead of a 3x3 product with dT. For T = Rz Ry Rx P the
// fixed-frame axes are e_z (yaw), Rz e_y (pitch) and Rz Ry e_x = T e_z (roll, about the
// optical axis: the film's own z).
#pragma once

#include <cmath>

#include <Eigen/Geometry>

#include "core/geometry/camera_model.hpp"

namespace ccdlane::solver {

class RoadProjection {
 public:
  // Per-pose constants from a CameraModel whose pose is set.
  void set_camera(const CameraModel& camera) {
    const CameraSpec& spec = camera.spec();
    const CameraPose& pose = camera.pose();
    const Mat3& T = camera.attitude_matrix();
    Tt_ = T.transpose();
    lens_in_film_ = Tt_ * (camera.lens_centre() - Vec3(0.0, 0.0, pose.H_mm));
    lens_seen_ = Tt_ * camera.lens_centre();
    const double cp = std::cos(pose.attitude.psi), sp = std::sin(pose.attitude.psi);
    axis_[kPsi] = Tt_.col(2);
    axis_[kTheta] = Tt_ * Vec3(-sp, cp, 0.0);
    axis_[kPhi] = Vec3::UnitZ();
    su_ = pose.f_mm / spec.pitch_u();
    sv_ = pose.f_mm / spec.pitch_v();
    inv_f_ = 1.0 / pose.f_mm;
    centre_ = camera.principal_point();
    k_ = spec.k_px2;
  }

  // The serial part of a projection (divisions and the square root), kept apart so that
  // a loop over many points runs these chains side by side instead of one after another.
  struct Chain {
    Vec3 d;           // T^T (X - L): the point seen from the lens, film frame
    Vec2 w;           // ideal pixel - principal point
    double iz = 0.0;  // 1 / d_z
    double gain = 0.0, dgain = 0.0;  // distortion gain g(rho) and dg/drho, rho = |w|^2
  };

  // First stage for road point (x, y, 0). False when the point is not in front of the
  // lens or beyond the distortion model's field (CameraModel's rules).
  bool start(double x, double y, Chain& c) const {
    c.d = x * Tt_.col(0) + y * Tt_.col(1) - lens_seen_;
    if (!(c.d.z() > 0.0)) return false;
    c.iz = 1.0 / c.d.z();
    c.w = Vec2(-su_ * c.d.x() * c.iz, -sv_ * c.d.y() * c.iz);
    // Division-model distortion (distortion.cpp): g = 2 / (1 + s), s = sqrt(1 - 4 k rho).
    const double disc = 1.0 - 4.0 * k_ * c.w.squaredNorm();
    if (!(disc > 0.0)) return false;
    const double s = std::sqrt(disc);
    const double t = 1.0 / (s * (1.0 + s));
    c.gain = 2.0 * s * t;
    c.dgain = 4.0 * k_ * t * s * t;
    return true;
  }

  // Second stage: the observed pixel.
  Vec2 pixel(const Chain& c) const { return centre_ + c.gain * c.w; }

  // Derivatives of the observed pixel, from a chain of the current pose.
  struct Derivatives {
    Eigen::Matrix<double, 2, 3> D;  // d(pixel) / d(d)
    Vec2 ow;                        // (d pixel / d w) w: the image scaling with f
    Vec3 seen;                      // T^T (X - H e3) = d + a
  };
  void derivatives(const Chain& c, Derivatives& out) const {
    const Vec2& w = c.w;
    const double iz = c.iz;
    // do/dw = g I + 2 g' w w^T, dw/dd = [[-su/dz, 0, -wx/dz], [0, -sv/dz, -wy/dz]].
    const double a = 2.0 * c.dgain;
    const double oxx = c.gain + a * w.x() * w.x(), oyy = c.gain + a * w.y() * w.y(), oxy = a * w.x() * w.y();
    out.ow = Vec2(oxx * w.x() + oxy * w.y(), oxy * w.x() + oyy * w.y());
    out.D << -oxx * su_ * iz, -oxy * sv_ * iz, -out.ow.x() * iz,
             -oxy * su_ * iz, -oyy * sv_ * iz, -out.ow.y() * iz;
    out.seen = c.d + lens_in_film_;
  }
  // Along the road's x (axis 0) or y (axis 1).
  Vec2 road_column(const Derivatives& d, int axis) const { return d.D * Tt_.col(axis); }
  // Over one pose parameter.
  Vec2 pose_column(const Derivatives& d, PoseParam p) const {
    switch (p) {
      case kHeight: return -(d.D * Tt_.col(2));
      // f moves the lens along the axis (d_z shrinks) and scales the ideal image.
      case kFocal: return -d.D.col(2) + d.ow * inv_f_;
      default: return d.D * d.seen.cross(axis_[p]);
    }
  }

 private:
  Mat3 Tt_;
  Vec3 lens_in_film_, lens_seen_;
  Vec3 axis_[3];
  double su_ = 1.0, sv_ = 1.0, inv_f_ = 1.0, k_ = 0.0;
  Vec2 centre_ = Vec2::Zero();
};

}  // namespace ccdlane::solver
