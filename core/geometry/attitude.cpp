// Attitude matrix and its angle derivatives, in closed form: the solver sets a pose on
// every cost evaluation, so this runs one sincos per angle and no matrix products.
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

}  // namespace

Mat3 attitude_matrix(const Attitude& a, Mat3* dT_dpsi, Mat3* dT_dtheta, Mat3* dT_dphi, Mat3* turning_axes) {
  const double cz = std::cos(a.psi), sz = std::sin(a.psi);
  const double cy = std::cos(a.theta), sy = std::sin(a.theta);
  const double cx = std::cos(a.phi), sx = std::sin(a.phi);
  // R = Rz Ry Rx written out; P then takes film x to R's second column, film y to its
  // third and film z (the optical axis, at zero angles fixed x) to its first.
  const Vec3 r0(cz * cy, sz * cy, -sy);
  const Vec3 r1(cz * sy * sx - sz * cx, sz * sy * sx + cz * cx, cy * sx);
  const Vec3 r2(cz * sy * cx + sz * sx, sz * sy * cx - cz * sx, cy * cx);
  Mat3 t;
  t << r1, r2, r0;
  // The turning axes: yaw about fixed z, pitch about Rz e_y, roll about Rz Ry e_x = r0.
  if (dT_dpsi) *dT_dpsi = turned(Vec3::UnitZ(), t);
  if (dT_dtheta) *dT_dtheta = turned(Vec3(-sz, cz, 0.0), t);
  if (dT_dphi) *dT_dphi = turned(r0, t);
  if (turning_axes) *turning_axes << Vec3::UnitZ(), Vec3(-sz, cz, 0.0), r0;
  return t;
}

}  // namespace ccdlane
