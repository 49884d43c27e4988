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
// has on a daylight road. Sampled on every second row, every 32nd pixel; nothing is
// allocated. Returns measure levels (min_contrast times levels_per_grey, or less).
float frame_contrast_threshold(const ImageView& image, std::span<const ScanRow> rows, float min_contrast,
                               float levels_per_grey);

// The same rule, also band by band down the picture: where a band of kBandRows scan rows
// is darker than the frame (a bridge's or a truck's shadow across the road, the far road
// beyond a car's headlights), its paint stands above it by less, and so does its
// texture. row_thresholds[r] (one per row) gets the lower of the frame's threshold and
// its band's, from the band's own level and noise; a band is never held above the
// frame's (a band of pale concrete in a dim picture). The band's level is its upper
// quartile, not its median: a car's back fills much of a far band's road. Returns the
// frame's threshold, as frame_contrast_threshold does.
float contrast_thresholds(const ImageView& image, std::span<const ScanRow> rows, float min_contrast,
                          float levels_per_grey, std::span<float> row_thresholds);

inline constexpr int kBandRows = 8;
inline constexpr double kBandLevelQuantile = 0.75;

// The road's brightness at and above which `min_contrast` holds as configured. Daylit
// roads lie at 72-78 grey levels (segA's asphalt) to 92-128 (TuSimple's concrete); at 70
// the same concrete with half the light (46-64) kept 0.7-0.9 of the threshold while its
// paint's contrast halved, and lost 9 points of own lines. At 100, segB's pale concrete
// gave a seam the threshold it needed to make a lane 3.1 m wide (docs/real-roads.md).
inline constexpr double kDaylightRoadLevel = 85.0;
// A bar's contrast is a mean over its pixels against its sides' means, so its noise is
// below the pixel noise: at 6 sigmas of the pixels a noise bar of that contrast is
// beyond chance on any frame. (9, the configured 10 levels' margin over the development
// set's daylight noise of 0.9-1.5, held dim and noisy pictures to daylight's threshold.
// 4 found more in dim pictures whose encoder had smoothed their noise, and with the
// level of 85 let a road's edge on asphalt through: docs/real-roads.md.)
inline constexpr double kThresholdNoiseSigmas = 6.0;
// And never below this share of `min_contrast`, however dark and clean the picture.
inline constexpr double kMinThresholdShare = 0.3;

}  // namespace ccdlane
