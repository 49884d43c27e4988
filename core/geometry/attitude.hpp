// The camera attitude matrix T = Rz(psi) Ry(theta) Rx(phi) P of docs/geometry.md, with derivatives.
#pragma once

#include "core/geometry/types.hpp"

namespace ccdlane {

// Yaw, pitch, roll of the camera in radians (docs/geometry.md "Attitude").
struct Attitude {
  double psi = 0.0;    // yaw, positive turns the view left
  double theta = 0.0;  // pitch, positive tips the view down to the road
  double phi = 0.0;    // roll about the viewing direction
};

// The same angles in degrees, as configuration files and people give them.
struct AttitudeDeg {
  double psi_deg = 0.0;
  double theta_deg = 0.0;
  double phi_deg = 0.0;

  bool operator==(const AttitudeDeg&) const = default;
};

// The sines and cosines of an attitude's angles, from which T follows without further
// trigonometry.
struct AttitudeTrig {
  double sin_psi = 0.0, cos_psi = 1.0, sin_theta = 0.0, cos_theta = 1.0, sin_phi = 0.0, cos_phi = 1.0;

  static AttitudeTrig of(const Attitude& a);
  // The trig of `to`, given that this is the trig of `from`: by the angle-sum formulas
  // when no angle moved by more than kSmallTurn (a solver's step; a few multiplications,
  // within a few ulp of of(to)), else of(to).
  AttitudeTrig moved(const Attitude& from, const Attitude& to) const;
  static constexpr double kSmallTurn = 0.125;  // radians

  // T (attitude_matrix below) from the trig. `turning_axes` receives the fixed-frame axes
  // (columns: yaw, pitch, roll) that a change of each angle turns the camera about:
  // dT = [w]x T.
  Mat3 matrix(Mat3* turning_axes = nullptr) const;
};

// The matrix mapping film-frame components to fixed-frame components. Each optional
// out-parameter receives the element-wise derivative of T with respect to that angle.
Mat3 attitude_matrix(const Attitude& a, Mat3* dT_dpsi = nullptr, Mat3* dT_dtheta = nullptr, Mat3* dT_dphi = nullptr);

}  // namespace ccdlane
