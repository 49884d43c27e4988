// Attitude matrix and its angle derivatives, in closed form: the solver sets a pose on
// every cost evaluation, so this runs one sincos per angle (none for a solver's small
// step, AttitudeTrig::moved) and no matrix products.
#include "core/geometry/attitude.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace ccdlane {
namespace {

// [w]x T: each column of T crossed with w from the left. For T = Rz Ry Rx P a change of
// one angle turns the camera about a fixed-frame axis w, so dT = [w]x T.
Mat3 turned(const Vec3& w, const Mat3& t) {
  Mat3 d;
  for (int k = 0; k < 3; ++k) d.col(k) = w.cross(t.col(k));
  return d;
}

// sin and cos of a + d from those of a, with d's own by their Taylor series to d^11 and
// d^12 (Horner, coefficients as constants: a division by 6.0 would be a division): for
// |d| <= 1/8 the remainders are below 1e-21 relative.
void add_small_angle(double d, double& s, double& c) {
  constexpr double s3 = -1.0 / 6, s5 = 1.0 / 120, s7 = -1.0 / 5040, s9 = 1.0 / 362880, s11 = -1.0 / 39916800;
  constexpr double c2 = -1.0 / 2, c4 = 1.0 / 24, c6 = -1.0 / 720, c8 = 1.0 / 40320, c10 = -1.0 / 3628800,
                   c12 = 1.0 / 479001600;
  const double d2 = d * d;
  const double sin_d = d + d * d2 * (s3 + d2 * (s5 + d2 * (s7 + d2 * (s9 + d2 * s11))));
  const double cos_d = 1.0 + d2 * (c2 + d2 * (c4 + d2 * (c6 + d2 * (c8 + d2 * (c10 + d2 * c12)))));
  const double s0 = s, c0 = c;
  s = s0 * cos_d + c0 * sin_d;
  c = c0 * cos_d - s0 * sin_d;
}

}  // namespace

AttitudeTrig AttitudeTrig::of(const Attitude& a) {
  return {std::sin(a.psi), std::cos(a.psi), std::sin(a.theta), std::cos(a.theta), std::sin(a.phi), std::cos(a.phi)};
}

AttitudeTrig AttitudeTrig::moved(const Attitude& from, const Attitude& to) const {
  const double d_psi = to.psi - from.psi, d_theta = to.theta - from.theta, d_phi = to.phi - from.phi;
  if (!(std::abs(d_psi) <= kSmallTurn && std::abs(d_theta) <= kSmallTurn && std::abs(d_phi) <= kSmallTurn))
    return of(to);
  AttitudeTrig t = *this;
  add_small_angle(d_psi, t.sin_psi, t.cos_psi);
  add_small_angle(d_theta, t.sin_theta, t.cos_theta);
  add_small_angle(d_phi, t.sin_phi, t.cos_phi);
  return t;
}

Mat3 AttitudeTrig::matrix(Mat3* turning_axes) const {
  const double cz = cos_psi, sz = sin_psi, cy = cos_theta, sy = sin_theta, cx = cos_phi, sx = sin_phi;
  // R = Rz Ry Rx written out; P then takes film x to R's second column, film y to its
  // third and film z (the optical axis, at zero angles fixed x) to its first.
  const Vec3 r0(cz * cy, sz * cy, -sy);
  const Vec3 r1(cz * sy * sx - sz * cx, sz * sy * sx + cz * cx, cy * sx);
  const Vec3 r2(cz * sy * cx + sz * sx, sz * sy * cx - cz * sx, cy * cx);
  Mat3 t;
  t << r1, r2, r0;
  // The turning axes: yaw about fixed z, pitch about Rz e_y, roll about Rz Ry e_x = r0.
  if (turning_axes) *turning_axes << Vec3::UnitZ(), Vec3(-sz, cz, 0.0), r0;
  return t;
}

Mat3 attitude_matrix(const Attitude& a, Mat3* dT_dpsi, Mat3* dT_dtheta, Mat3* dT_dphi) {
  Mat3 axes;
  const Mat3 t = AttitudeTrig::of(a).matrix(&axes);
  if (dT_dpsi) *dT_dpsi = turned(axes.col(0), t);
  if (dT_dtheta) *dT_dtheta = turned(axes.col(1), t);
  if (dT_dphi) *dT_dphi = turned(axes.col(2), t);
  return t;
}

}  // namespace ccdlane
