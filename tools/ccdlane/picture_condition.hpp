// Pictures as another camera or another light would have taken them: softer optics, less
// light, more sensor noise. `ccdlane replay --condition` measures with them how detection
// holds up away from the pictures it was developed on (tools/measure-real --conditions).
// A measuring instrument for the tool, never in the daemon's path.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/image_view.hpp"

namespace ccdlane::cli {

struct PictureCondition {
  double blur_px = 0.0;  // Gaussian blur, its sigma in pixels: defocus, a dirty windscreen, motion
  double light = 1.0;    // share of the light: every level times this (dusk, an underexposed camera)
  double noise = 0.0;    // Gaussian sensor noise added after the light, its sigma in 8-bit levels

  bool identity() const { return blur_px == 0.0 && light == 1.0 && noise == 0.0; }
  bool operator==(const PictureCondition&) const = default;
};

// "blur=1.5,light=0.3,noise=3" (any of the three, in any order; "" is the picture as
// recorded). Throws std::invalid_argument naming the bad part: an unknown key, a value
// that is not a number, blur or noise outside [0, 20], light outside (0, 4].
PictureCondition parse_picture_condition(const std::string& spec);

// The conditioned copy of each frame: blurred, then scaled, then the noise added (optics,
// exposure, sensor), rounded and clipped to the format's levels. The noise is drawn from a
// generator seeded with the frame's number, so a replay is repeatable and each frame's
// noise its own. Colour pixels are altered channel by channel.
class PictureConditioner {
 public:
  explicit PictureConditioner(PictureCondition condition) : condition_(condition) {}
  // The conditioned frame, valid until the next call; `frame` itself when the condition
  // is the identity.
  ImageView apply(const ImageView& frame, std::uint64_t frame_number);

 private:
  PictureCondition condition_;
  std::vector<std::uint8_t> pixels_;
};

}  // namespace ccdlane::cli
