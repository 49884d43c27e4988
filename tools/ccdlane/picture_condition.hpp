// Pictures as another camera or another light would have taken them: softer optics, less
// light, more sensor noise. `ccdlane replay --condition` measures with them how detection
// holds up away from the pictures it was developed on (tools/measure-real --conditions).
// A measuring instrument for the tool, never in the daemon's path.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/image_view.hpp"
#include "core/geometry/camera_spec.hpp"

namespace ccdlane::cli {

struct PictureCondition {
  double blur_px = 0.0;  // Gaussian blur, its sigma in pixels: defocus, a dirty windscreen, motion
  double light = 1.0;    // share of the light: every level times this (dusk, an underexposed camera)
  double noise = 0.0;    // Gaussian sensor noise added after the light, its sigma in 8-bit levels
  // A shadow across the whole picture (an overpass's, a bridge's): the rows from
  // shade_top to shade_bottom (shares of the picture's height; by default 55-70 %, the
  // road 10-30 m ahead of a forward car camera) get this share of the light, with an
  // edge as soft as 1 % of the height on either side (the penumbra). 1: no shadow.
  double shade = 1.0;
  double shade_top = 0.55, shade_bottom = 0.70;
  // Trees' shadows over the road: patches of this share of the light over `dapple_cover`
  // of the picture's lower half (the road), wider than tall as the road's perspective
  // makes them, with soft edges (the sun's half degree at a tree's height), drifting
  // down the picture from frame to frame as a car drives under them. 1: none.
  double dapple = 1.0;
  double dapple_cover = 0.4;
  // Another camera's pixel count: the picture resized by this along each side, as a chip
  // of the same size behind the same lens with cells 1/scale as wide would take it
  // (camera_taking). Applied first, so that blur and noise are in that camera's pixels.
  double scale = 1.0;
  // The picture through a JPEG encoder at this quality (1-100) and back, last, as a
  // dashcam's, a video stream's or a dataset's compression leaves it. 0: not compressed.
  double jpeg = 0.0;

  bool identity() const {
    return scale == 1.0 && blur_px == 0.0 && light == 1.0 && noise == 0.0 && shade == 1.0 && dapple == 1.0 &&
           jpeg == 0.0;
  }
  bool operator==(const PictureCondition&) const = default;
};

// "scale=1.5,blur=1.5,light=0.3,noise=3,shade=0.3,dapple=0.4,jpeg=50" (any of them, in
// any order; "" is the picture as recorded). Throws std::invalid_argument naming the bad
// part: an unknown key, a value that is not a number, scale outside [0.25, 4], blur or
// noise outside [0, 20], light outside (0, 4], shade or dapple outside (0, 1], shade_top
// or shade_bottom outside [0, 1] or not top above bottom, dapple_cover outside [0.05,
// 0.95], jpeg outside [1, 100].
PictureCondition parse_picture_condition(const std::string& spec);

// The camera whose pictures `condition` makes of `camera`'s: round(scale x) the cells
// along each side, each as much narrower, on the same chip behind the same lens; the
// principal point where the resize puts it and the distortion in its pixels (k / scale^2:
// the division model's k r^2 is the same at every point). A road point's pixel in its
// pictures is (pixel - 0.5) x scale + 0.5 of `camera`'s (1-based).
CameraSpec camera_taking(const PictureCondition& condition, const CameraSpec& camera);

// The conditioned copy of each frame: resized (area-averaged when smaller, bilinear when
// larger: no ringing a camera's own pixels would not have), blurred, then its levels
// scaled (and shaded, and dappled), then the noise added (pixels, optics, light, sensor),
// rounded and clipped to the format's levels, then compressed and decoded (the camera's
// encoder). The noise is drawn from a generator seeded with the frame's number, so a
// replay is repeatable and each frame's noise its own. Colour pixels are altered channel
// by channel.
class PictureConditioner {
 public:
  explicit PictureConditioner(PictureCondition condition) : condition_(condition) {}
  // The conditioned frame (camera_taking's size), valid until the next call; `frame`
  // itself when the condition is the identity.
  // A 16-bit frame with jpeg= throws std::invalid_argument, libjpeg's failure
  // std::runtime_error.
  ImageView apply(const ImageView& frame, std::uint64_t frame_number);

 private:
  PictureCondition condition_;
  std::vector<std::uint8_t> pixels_;
  std::vector<float> dapple_field_;  // the trees' shadows, 0-1, drawn once per picture size
  int dapple_width_ = 0, dapple_height_ = 0;
};

}  // namespace ccdlane::cli
