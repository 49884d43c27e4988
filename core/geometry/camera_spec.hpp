// The fixed description of a camera: its CCD array, principal point, distortion and mount.
#pragma once

namespace ccdlane {

// Everything about the camera that does not change while driving (docs/geometry.md
// "Mount and lens", "Pixels and chip cells", "Radial distortion"). Lengths in mm.
struct CameraSpec {
  double U_mm = 6.4;      // active chip width
  double V_mm = 4.8;      // active chip height
  double Uc_mm = 0.0042;  // one cell's width
  double Vc_mm = 0.0042;  // one cell's height
  int Nu = 800;           // pixels per row
  int Nv = 600;           // rows
  double cx = 400.5;      // principal point, 1-based pixels
  double cy = 300.5;
  double k_px2 = 0.0;  // division-model radial distortion, 1/px^2
  double yM_mm = 0.0;  // mounting point in the film frame (0, yM, zM)
  double zM_mm = 0.0;

  double pitch_u() const { return (U_mm - Uc_mm) / (Nu - 1); }  // mm per pixel along a row
  double pitch_v() const { return (V_mm - Vc_mm) / (Nv - 1); }  // mm per pixel down a column
  static double default_cx(int nu) { return (nu + 1) / 2.0; }
  static double default_cy(int nv) { return (nv + 1) / 2.0; }
  bool operator==(const CameraSpec&) const = default;
};

}  // namespace ccdlane
