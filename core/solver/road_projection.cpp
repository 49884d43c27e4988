// The solver's projection kernel as passes over the points (see the header).
#include "core/solver/road_projection.hpp"

#include <cmath>

#include "core/geometry/attitude.hpp"

namespace ccdlane::solver {

RoadProjection::Covectors::Covectors(int max_points) {
  for (auto* v : {&film, &turn, &film_across, &turn_across})
    for (Array& a : *v) a.setZero(max_points);
}

RoadProjection::RoadProjection(const CameraSpec& spec, int max_points)
    : spec_(spec),
      inv_pitch_u_(1.0 / spec.pitch_u()),
      inv_pitch_v_(1.0 / spec.pitch_v()),
      centre_(spec.cx, spec.cy),
      k_(spec.k_px2) {
  for (Array* a : {&dx_, &dy_, &dz_, &iz_, &wx_, &wy_, &gain_, &dgain_, &u_, &v_, &oxx_, &oxy_, &oyy_, &scratch_})
    a->setZero(max_points);
}

void RoadProjection::set_pose(const CameraPose& pose) {
  // From the previous pose's trig by the step between them: the solver's poses move in
  // small steps, and three sincos calls would cost a fifth of a 20-pick cost evaluation.
  trig_ = has_trig_ ? trig_.moved(trig_angles_, pose.attitude) : AttitudeTrig::of(pose.attitude);
  trig_angles_ = pose.attitude;
  has_trig_ = true;
  Mat3 turning_axes;
  Tt_ = trig_.matrix(&turning_axes).transpose();
  axes_in_film_ = Tt_ * turning_axes;
  // L - H e3 = T a with a the lens in film components, so T^T (X - L) = T^T X - a - H T^T e3.
  lens_in_film_ = CameraModel::lens_in_film(spec_, pose.f_mm);
  lens_seen_ = lens_in_film_ + pose.H_mm * Tt_.col(2);
  f_ = pose.f_mm;
  su_ = pose.f_mm * inv_pitch_u_;
  sv_ = pose.f_mm * inv_pitch_v_;
}

bool RoadProjection::project(const Array& x, const Array& y, int n) {
  const double *X = x.data(), *Y = y.data();
  double *dx = dx_.data(), *dy = dy_.data(), *dz = dz_.data(), *iz = iz_.data();
  double *wx = wx_.data(), *wy = wy_.data(), *gain = gain_.data(), *dgain = dgain_.data();
  double *u = u_.data(), *v = v_.data();
  // Locals, not members: the stores below could alias members, which would keep the
  // compiler from vectorising the loop.
  const Mat3 t = Tt_;
  const Vec3 o = lens_seen_;
  const double su = su_, sv = sv_, k = k_, cx = centre_.x(), cy = centre_.y();
  double* seen = scratch_.data();  // 1 where the point can be seen, else 0
  // One pass without a branch, so that it vectorises: a point that cannot be seen makes
  // NaNs or infinities of its own values only, and is found after the loop.
  // The arrays are distinct (no point's output is another's input): no alias checks.
#pragma GCC ivdep
  for (int i = 0; i < n; ++i) {
    const double z = X[i] * t(2, 0) + Y[i] * t(2, 1) - o.z();
    const double xf = X[i] * t(0, 0) + Y[i] * t(0, 1) - o.x(), yf = X[i] * t(1, 0) + Y[i] * t(1, 1) - o.y();
    const double inv_z = 1.0 / z;
    const double px = -su * xf * inv_z, py = -sv * yf * inv_z;
    // Division-model distortion (distortion.cpp): g = 2 / (1 + s), s = sqrt(1 - 4 k rho),
    // rho = |w|^2, written as g = 2 s t with t = 1 / (s (1 + s)), and dg/drho = 2 k t g.
    const double s2 = 1.0 - 4.0 * k * (px * px + py * py);
    // In front of the lens and inside the distortion model's field (NaNs fail both).
    seen[i] = (z > 0.0) & (s2 > 0.0) ? 1.0 : 0.0;
    const double s = std::sqrt(s2);
    const double tt = 1.0 / (s * (1.0 + s));
    const double g = 2.0 * s * tt;
    dx[i] = xf;
    dy[i] = yf;
    dz[i] = z;
    iz[i] = inv_z;
    wx[i] = px;
    wy[i] = py;
    gain[i] = g;
    dgain[i] = 2.0 * k * tt * g;
    u[i] = cx + g * px;
    v[i] = cy + g * py;
  }
  return n == 0 || scratch_.head(n).minCoeff() > 0.0;  // a vectorised reduction
}

// d w / d d = -(1 / d_z) [[su, 0, w_x], [0, sv, w_y]]: the ideal pixel w = -(su d_x, sv d_y) / d_z.

void RoadProjection::differentiate(const Array& slope, double scale, int n, Array& du, Array& dv) {
  const double* s = slope.data();
  const double *iz = iz_.data(), *wx = wx_.data(), *wy = wy_.data(), *gain = gain_.data(), *dgain = dgain_.data();
  double *oxx = oxx_.data(), *oxy = oxy_.data(), *oyy = oyy_.data();
  double *out_u = du.data(), *out_v = dv.data();
  const Vec3 e0 = Tt_.col(0), e1 = Tt_.col(1);  // road x and road y in film components
  const double su = su_, sv = sv_;              // locals: see project()
  // The arrays are distinct (no point's output is another's input): no alias checks.
#pragma GCC ivdep
  for (int i = 0; i < n; ++i) {
    // d pixel / d w = g I + 2 g' w w^T, kept for pull_back().
    const double a = 2.0 * dgain[i];
    const double o_xy = a * wx[i] * wy[i], o_xx = gain[i] + a * wx[i] * wx[i], o_yy = gain[i] + a * wy[i] * wy[i];
    oxx[i] = o_xx;
    oxy[i] = o_xy;
    oyy[i] = o_yy;
    // The road direction e = (1, slope, 0) in film components, through d w / d d.
    const double ex = e0.x() + s[i] * e1.x(), ey = e0.y() + s[i] * e1.y(), ez = e0.z() + s[i] * e1.z();
    const double m = -scale * iz[i];
    const double dwx = m * (su * ex + wx[i] * ez), dwy = m * (sv * ey + wy[i] * ez);
    out_u[i] = o_xx * dwx + o_xy * dwy;
    out_v[i] = o_xy * dwx + o_yy * dwy;
  }
}

namespace {

// Point i's film covector f and its turn covector f x s into three arrays each.
inline void put_covector(double* const film[3], double* const turn[3], int i, double f0, double f1, double f2,
                         double sx, double sy, double sz) {
  film[0][i] = f0;
  film[1][i] = f1;
  film[2][i] = f2;
  turn[0][i] = f1 * sz - f2 * sy;
  turn[1][i] = f2 * sx - f0 * sz;
  turn[2][i] = f0 * sy - f1 * sx;
}

}  // namespace

void RoadProjection::pull_back(const Array& b0, const Array& b1, double scale, int n, Covectors& out) const {
  const double *p0 = b0.data(), *p1 = b1.data();
  const double *dx = dx_.data(), *dy = dy_.data(), *dz = dz_.data(), *iz = iz_.data();
  const double *wx = wx_.data(), *wy = wy_.data(), *oxx = oxx_.data(), *oxy = oxy_.data(), *oyy = oyy_.data();
  double* const film[3] = {out.film[0].data(), out.film[1].data(), out.film[2].data()};
  double* const turn[3] = {out.turn[0].data(), out.turn[1].data(), out.turn[2].data()};
  double* const film_across[3] = {out.film_across[0].data(), out.film_across[1].data(), out.film_across[2].data()};
  double* const turn_across[3] = {out.turn_across[0].data(), out.turn_across[1].data(), out.turn_across[2].data()};
  const Vec3 a = lens_in_film_;
  const double su = su_, sv = sv_;  // locals: see project()
  // The arrays are distinct (no point's output is another's input): no alias checks.
#pragma GCC ivdep
  for (int i = 0; i < n; ++i) {
    const double c0 = scale * p0[i], c1 = scale * p1[i];
    // rho = b^T d pixel / d w (symmetric), for b = (c0, c1) and (-c1, c0).
    const double rx = c0 * oxx[i] + c1 * oxy[i], ry = c0 * oxy[i] + c1 * oyy[i];
    const double qx = c0 * oxy[i] - c1 * oxx[i], qy = c0 * oyy[i] - c1 * oxy[i];
    // film = rho^T d w / d d; turn = film x (d + a).
    const double m = -iz[i], sx = dx[i] + a.x(), sy = dy[i] + a.y(), sz = dz[i] + a.z();
    put_covector(film, turn, i, m * su * rx, m * sv * ry, m * (rx * wx[i] + ry * wy[i]), sx, sy, sz);
    put_covector(film_across, turn_across, i, m * su * qx, m * sv * qy, m * (qx * wx[i] + qy * wy[i]), sx, sy, sz);
  }
}

namespace {

using Vectors = std::array<Eigen::ArrayXd, 3>;

// w . v[i] into a[i] and w . c[i] into b[i], for a direction w fixed over the points.
void dot(const Vec3& w, const Vectors& v, const Vectors& c, int n, Eigen::ArrayXd& a, Eigen::ArrayXd& b) {
  const double *v0 = v[0].data(), *v1 = v[1].data(), *v2 = v[2].data();
  const double *c0 = c[0].data(), *c1 = c[1].data(), *c2 = c[2].data();
  const double w0 = w.x(), w1 = w.y(), w2 = w.z();
  double *out_a = a.data(), *out_b = b.data();
#pragma GCC ivdep
  for (int i = 0; i < n; ++i) {
    out_a[i] = v0[i] * w0 + v1[i] * w1 + v2[i] * w2;
    out_b[i] = c0[i] * w0 + c1[i] * w1 + c2[i] * w2;
  }
}

}  // namespace

void RoadProjection::road_along(const Covectors& b, int axis, int n, Array& along, Array& across) const {
  dot(Tt_.col(axis), b.film, b.film_across, n, along, across);
}

void RoadProjection::pose_along(const Covectors& b, PoseParam p, int n, Array& along, Array& across) const {
  switch (p) {
    case kHeight: dot(-Tt_.col(2), b.film, b.film_across, n, along, across); return;
    case kFocal: {
      // f moves the lens along the axis (d_z shrinks by 1) and scales the ideal image:
      // d pixel / d f = -D e_z + (d pixel / d w) w / f, and b^T (d pixel / d w) w = -film_z d_z.
      const auto gain = -(1.0 + dz_.head(n) * (1.0 / f_));
      along.head(n) = b.film[2].head(n) * gain;
      across.head(n) = b.film_across[2].head(n) * gain;
      return;
    }
    default: dot(axes_in_film_.col(p), b.turn, b.turn_across, n, along, across);
  }
}

}  // namespace ccdlane::solver
