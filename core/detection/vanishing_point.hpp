// The road's vanishing point found in the picture, without trusting a pose. Everything
// that runs along the road draws edges that meet there: lane paint, Botts' dots in a row,
// concrete seams, tyre tracks, kerbs and barrier feet. Each edge pixel below the horizon
// votes along its own direction for where the point may be (an accumulator over the
// picture region that the mount's yaw and pitch bounds allow); the strongest crossing is
// the vanishing point. Edges across the road (shadows, bumpers) are left out; the other
// clutter (cars, poles) votes for no point in common. This is the classic texture vote
// for a road's vanishing point, on a budget: subsampled pixels, one row of bins per row
// of the search region.
//
// This is how detection starts when it has no pose to trust (a cold start, a still):
// the vanishing point gives the camera's yaw and pitch to the lane (attitude_from_
// vanishing_point), and only then are marks projected onto the road and grouped.
#pragma once

#include <optional>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/detection_config.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane {

struct VanishingPoint {
  bool found = false;
  double x = 0.0, y = 0.0;  // ideal 1-based pixel
  double strength = 0.0;    // the peak's votes over the mean cell's (3x3 sums): how clear it is
  int edges = 0;            // edge pixels that voted
  // The region searched (ideal pixels), for overlays.
  double x_lo = 0.0, x_hi = 0.0, y_lo = 0.0, y_hi = 0.0;
};

// How far from the nominal mount the road's direction is searched for.
struct VanishingPointSearch {
  double max_pitch_error_deg = 10.0;
  double max_yaw_error_deg = 10.0;
};

// Sets r's region (x_lo .. y_hi, ideal pixels) to where the road's direction appears for
// a camera mounted within `search`'s bounds of `nominal`.
void set_search_region(const CameraSpec& camera, const CameraPose& nominal, const VanishingPointSearch& search,
                       VanishingPoint& r);

class VanishingPointFinder {
 public:
  // Sizes every buffer for frames of camera.Nu x camera.Nv; find() never allocates.
  VanishingPointFinder(const CameraSpec& camera, const DetectionConfig& config,
                       const VanishingPointSearch& search = {});

  // The vanishing point of the road seen in `image` by a camera mounted near `nominal`
  // (its roll and focal length; yaw and pitch within the search's bounds). The result
  // stays valid until the next call.
  const VanishingPoint& find(const ImageView& image, const CameraPose& nominal);

  // A peak this many times the mean cell is a vanishing point (noise and clutter give 2-3).
  static constexpr double kMinStrength = 4.0;

 private:
  void set_region(const CameraPose& nominal);
  void vote_row(const ImageView& image, int y);
  void choose_peak();

  CameraSpec camera_;
  DetectionConfig config_;
  VanishingPointSearch search_;
  std::vector<std::uint16_t> rows_[3];  // the paint measure of three picture rows
  std::vector<float> votes_;            // bins_y x bins_x, edges leaning left (dx/dy < 0)
  std::vector<float> votes_right_;      // and right
  int bins_x_ = 0, bins_y_ = 0;
  double bin_px_ = 4.0;
  VanishingPoint result_;
};

// The camera attitude whose view of the road direction (1, 0, 0) lies at the ideal pixel
// (vp_x, vp_y), with `pose`'s roll, height and focal length (its yaw and pitch are the
// starting guess). Empty when no yaw and pitch within 30 degrees put it there.
std::optional<Attitude> attitude_from_vanishing_point(const CameraSpec& camera, const CameraPose& pose, double vp_x,
                                                      double vp_y);

}  // namespace ccdlane
