// Attitude matrix and its angle derivatives, written out from the elementary rotations.
#include "core/geometry/attitude.hpp"

#include <cmath>

namespace ccdlane {
namespace {

Mat3 rot_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}
Mat3 rot_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}
Mat3 rot_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}
// d/da of the elementary rotations.
Mat3 rot_z_d(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << -s, -c, 0, c, -s, 0, 0, 0, 0;
  return r;
}
Mat3 rot_y_d(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << -s, 0, c, 0, 0, 0, -c, 0, -s;
  return r;
}
Mat3 rot_x_d(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 r;
  r << 0, 0, 0, 0, -s, -c, 0, c, -s;
  return r;
}

// Film axes (x right along a row, y down a column, z along the optical axis) expressed
// in the fixed frame when all angles are zero: the optical axis looks along +x.
Mat3 film_to_level() {
  Mat3 p;
  p << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  return p;
}

}  // namespace

Mat3 attitude_matrix(const Attitude& a, Mat3* dT_dpsi, Mat3* dT_dtheta, Mat3* dT_dphi) {
  const Mat3 rz = rot_z(a.psi), ry = rot_y(a.theta), rx = rot_x(a.phi);
  const Mat3 p = film_to_level();
  if (dT_dpsi) *dT_dpsi = rot_z_d(a.psi) * ry * rx * p;
  if (dT_dtheta) *dT_dtheta = rz * rot_y_d(a.theta) * rx * p;
  if (dT_dphi) *dT_dphi = rz * ry * rot_x_d(a.phi) * p;
  return rz * ry * rx * p;
}

}  // namespace ccdlane
