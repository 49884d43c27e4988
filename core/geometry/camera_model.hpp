// A camera at a pose: pixel <-> chip cell <-> fixed frame, road point -> pixel and back.
#pragma once

#include <optional>

#include "core/geometry/attitude.hpp"
#include "core/geometry/camera_spec.hpp"
#include "core/geometry/types.hpp"

namespace ccdlane {

// The quantities the solver may estimate about the camera (docs/geometry.md), in the order
// used by every pose Jacobian below.
enum PoseParam : int { kPsi = 0, kTheta = 1, kPhi = 2, kHeight = 3, kFocal = 4, kPoseParams = 5 };

struct CameraPose {
  Attitude attitude;  // radians
  double H_mm = 0.0;  // height of the mounting point above the road
  double f_mm = 0.0;  // focal length (lens centre to chip)
};

using PoseJacobian2 = Eigen::Matrix<double, 2, kPoseParams>;
using PoseJacobian3 = Eigen::Matrix<double, 3, kPoseParams>;
using PointJacobian = Eigen::Matrix<double, 2, 3>;

class CameraModel {
 public:
  CameraModel(const CameraSpec& spec, const CameraPose& pose);

  // Recomputes T, its derivatives, the chip origin and the lens centre. Cheap (no
  // allocation), so the solver calls it once per iteration.
  void set_pose(const CameraPose& pose);

  const CameraSpec& spec() const { return spec_; }
  const CameraPose& pose() const { return pose_; }
  const Mat3& attitude_matrix() const { return T_; }
  Vec2 principal_point() const { return {spec_.cx, spec_.cy}; }
  Vec3 chip_origin() const;                                 // O_F, fixed frame
  Vec3 lens_centre(PoseJacobian3* d_pose = nullptr) const;  // L, fixed frame
  // L - H e3 in film components, (0, -yM, f - zM): where the lens sits from the mount.
  static Vec3 lens_in_film(const CameraSpec& spec, double f_mm) { return {0.0, -spec.yM_mm, f_mm - spec.zM_mm}; }

  // 1-based ideal pixel <-> film-frame chip coordinates (x̄, ȳ) in mm, z̄ = 0.
  Vec2 chip_from_pixel(const Vec2& ideal_px) const;
  Vec2 pixel_from_chip(const Vec2& chip_mm) const;

  // The fixed-frame centre of the cell at an ideal pixel (P_pix).
  Vec3 cell_centre(const Vec2& ideal_px, PoseJacobian3* d_pose = nullptr) const;

  // Distortion about this camera's principal point (see distortion.hpp).
  std::optional<Vec2> ideal_from_observed(const Vec2& observed_px) const;
  std::optional<Vec2> observed_from_ideal(const Vec2& ideal_px, Mat2* d_observed_d_ideal = nullptr) const;

  // Fixed-frame point -> ideal pixel. Empty when the point is not in front of the lens.
  std::optional<Vec2> ideal_pixel_from_point(const Vec3& point_mm, PointJacobian* d_point = nullptr,
                                             PoseJacobian2* d_pose = nullptr) const;
  // Fixed-frame point -> observed (distorted) pixel, what a pick is compared with.
  std::optional<Vec2> pixel_from_point(const Vec3& point_mm, PointJacobian* d_point = nullptr,
                                       PoseJacobian2* d_pose = nullptr) const;

  // Ray-ground intersection (z = 0). Empty at or above the horizon, or for an observed
  // pixel with no ideal counterpart.
  std::optional<Vec3> ground_point_from_ideal_pixel(const Vec2& ideal_px) const;
  std::optional<Vec3> ground_point_from_pixel(const Vec2& observed_px) const;

 private:
  CameraSpec spec_;
  CameraPose pose_;
  Mat3 T_;
  Mat3 dT_[3];         // dT/dpsi, dT/dtheta, dT/dphi
  Vec3 lens_in_film_;  // L - H e3 in film components: (0, -yM, f - zM)
};

}  // namespace ccdlane
