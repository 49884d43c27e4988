// The contrast paint must stand above the road by in one frame: the configured minimum
// in daylight, less on a dim road (dusk, overcast, an underexposed camera), never below
// what the picture's noise makes by chance.
#pragma once

#include <span>

#include "base/image_view.hpp"
#include "core/detection/scan_row.hpp"

namespace ccdlane {

// Paint reflects a share of the light the road does, so its contrast falls with the
// road's brightness: the threshold is `min_contrast` (grey levels, 8-bit scale) in
// proportion to the road's median level on the scan rows, up to a daylight road's
// (kDaylightRoadLevel), and at least kThresholdNoiseSigmas times the pixel noise measured
// on the same rows (adjacent pixels' differences): the margin over noise `min_contrast`
// has on a daylight road. Sampled on every eighth row, every sixteenth pixel; nothing is
// allocated. Returns measure levels (min_contrast times levels_per_grey, or less).
float frame_contrast_threshold(const ImageView& image, std::span<const ScanRow> rows, float min_contrast,
                               float levels_per_grey);

// The road's brightness at and above which `min_contrast` holds as configured: the
// darkest daylight road of the development set (segA's asphalt, median 72-78 grey levels;
// TuSimple's concrete 92-128).
inline constexpr double kDaylightRoadLevel = 70.0;
// The configured 10 levels are 8-10 times the pixel noise (0.9-1.5 grey levels) of the
// development set's daylight pictures.
inline constexpr double kThresholdNoiseSigmas = 9.0;
// And never below this share of `min_contrast`, however dark and clean the picture.
inline constexpr double kMinThresholdShare = 0.3;

}  // namespace ccdlane
