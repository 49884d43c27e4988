// The solver's projection kernel as array expressions (see the header).
#include "core/solver/road_projection.hpp"

#include <cmath>

#include "core/geometry/attitude.hpp"

namespace ccdlane::solver {

RoadProjection::RoadProjection(int max_points) {
  for (Array* a : {&dx_, &dy_, &dz_, &iz_, &wx_, &wy_, &gain_, &dgain_, &u_, &v_, &D00_, &D01_, &D02_, &D10_,
                   &D11_, &D12_, &owx_, &owy_, &seen_x_, &seen_y_, &seen_z_, &scratch_})
    a->setZero(max_points);
  axis_[0] = axis_[1] = axis_[2] = Vec3::UnitZ();
}

void RoadProjection::set_camera(const CameraSpec& spec, const CameraPose& pose) {
  Tt_ = attitude_matrix(pose.attitude).transpose();
  // L - H e3 = T a with a the lens in film components, so T^T (X - L) = T^T X - a - H T^T e3.
  lens_in_film_ = CameraModel::lens_in_film(spec, pose.f_mm);
  lens_seen_ = lens_in_film_ + pose.H_mm * Tt_.col(2);
  const double cp = std::cos(pose.attitude.psi), sp = std::sin(pose.attitude.psi);
  axis_[kPsi] = Tt_.col(2);
  axis_[kTheta] = Tt_ * Vec3(-sp, cp, 0.0);
  axis_[kPhi] = Vec3::UnitZ();
  su_ = pose.f_mm / spec.pitch_u();
  sv_ = pose.f_mm / spec.pitch_v();
  inv_f_ = 1.0 / pose.f_mm;
  centre_ = Vec2(spec.cx, spec.cy);
  k_ = spec.k_px2;
}

bool RoadProjection::project(const Array& x, const Array& y, int n) {
  const auto X = x.head(n), Y = y.head(n);
  auto dx = dx_.head(n), dy = dy_.head(n), dz = dz_.head(n), iz = iz_.head(n);
  dz = X * Tt_(2, 0) + Y * Tt_(2, 1) - lens_seen_.z();
  if (!(dz > 0.0).all()) return false;
  dx = X * Tt_(0, 0) + Y * Tt_(0, 1) - lens_seen_.x();
  dy = X * Tt_(1, 0) + Y * Tt_(1, 1) - lens_seen_.y();
  iz = dz.inverse();
  auto wx = wx_.head(n), wy = wy_.head(n);
  wx = -su_ * dx * iz;
  wy = -sv_ * dy * iz;
  // Division-model distortion (distortion.cpp): g = 2 / (1 + s), s = sqrt(1 - 4 k rho),
  // rho = |w|^2, written as g = 2 s t with t = 1 / (s (1 + s)), and dg/drho = 2 k t g.
  auto s = scratch_.head(n), gain = gain_.head(n), dgain = dgain_.head(n);
  s = 1.0 - 4.0 * k_ * (wx * wx + wy * wy);
  if (!(s > 0.0).all()) return false;
  s = s.sqrt();
  dgain = (s * (1.0 + s)).inverse();  // t, for now
  gain = 2.0 * s * dgain;
  dgain = 2.0 * k_ * dgain * gain;
  u_.head(n) = centre_.x() + gain * wx;
  v_.head(n) = centre_.y() + gain * wy;
  return true;
}

void RoadProjection::differentiate(int n) {
  const auto wx = wx_.head(n), wy = wy_.head(n), iz = iz_.head(n), gain = gain_.head(n);
  // d pixel / d w = g I + 2 g' w w^T; its (xx, yy) entries go through D00/D11 first.
  auto a = scratch_.head(n), oxy = D01_.head(n), oxx = D00_.head(n), oyy = D11_.head(n);
  a = 2.0 * dgain_.head(n);
  oxy = a * wx * wy;
  oxx = gain + a * wx * wx;
  oyy = gain + a * wy * wy;
  owx_.head(n) = oxx * wx + oxy * wy;
  owy_.head(n) = oxy * wx + oyy * wy;
  // D = (d pixel / d w)(d w / d d), d w / d d = [[-su/dz, 0, -wx/dz], [0, -sv/dz, -wy/dz]].
  D02_.head(n) = -owx_.head(n) * iz;
  D12_.head(n) = -owy_.head(n) * iz;
  D10_.head(n) = -oxy * su_ * iz;
  D01_.head(n) = -oxy * sv_ * iz;  // oxy's last use
  D00_.head(n) = -oxx * su_ * iz;
  D11_.head(n) = -oyy * sv_ * iz;
  seen_x_.head(n) = dx_.head(n) + lens_in_film_.x();
  seen_y_.head(n) = dy_.head(n) + lens_in_film_.y();
  seen_z_.head(n) = dz_.head(n) + lens_in_film_.z();
}

void RoadProjection::fixed_direction(const Vec3& w, int n, Array& du, Array& dv) const {
  du.head(n) = D00_.head(n) * w.x() + D01_.head(n) * w.y() + D02_.head(n) * w.z();
  dv.head(n) = D10_.head(n) * w.x() + D11_.head(n) * w.y() + D12_.head(n) * w.z();
}

void RoadProjection::road_column(int axis, int n, Array& du, Array& dv) const {
  fixed_direction(Tt_.col(axis), n, du, dv);
}

void RoadProjection::pose_column(PoseParam p, int n, Array& du, Array& dv) const {
  switch (p) {
    case kHeight: fixed_direction(-Tt_.col(2), n, du, dv); return;
    case kFocal:  // f moves the lens along the axis (d_z shrinks) and scales the ideal image.
      du.head(n) = -D02_.head(n) + owx_.head(n) * inv_f_;
      dv.head(n) = -D12_.head(n) + owy_.head(n) * inv_f_;
      return;
    default: {
      // D (seen x axis), the cross product written out per point.
      const Vec3& a = axis_[p];
      const auto sx = seen_x_.head(n), sy = seen_y_.head(n), sz = seen_z_.head(n);
      du.head(n) = D00_.head(n) * (sy * a.z() - sz * a.y()) + D01_.head(n) * (sz * a.x() - sx * a.z()) +
                   D02_.head(n) * (sx * a.y() - sy * a.x());
      dv.head(n) = D10_.head(n) * (sy * a.z() - sz * a.y()) + D11_.head(n) * (sz * a.x() - sx * a.z()) +
                   D12_.head(n) * (sx * a.y() - sy * a.x());
    }
  }
}

}  // namespace ccdlane::solver
