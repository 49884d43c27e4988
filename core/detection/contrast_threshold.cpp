// The frame's contrast threshold from the road's level and noise on the scan rows.
#include "core/detection/contrast_threshold.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "core/detection/paint_measure.hpp"

namespace ccdlane {
namespace {

constexpr int kRowStep = 8;
constexpr int kPixelStep = 16;
// A difference larger than this is an edge (paint, a car, a shadow's border), not noise.
constexpr int kMaxNoiseStep = 20;
// The standard deviation of a Gaussian from the mean absolute difference of two of its
// samples: E|a - b| = 2 sigma / sqrt(pi).
const double kSigmaPerMeanDifference = std::sqrt(std::acos(-1.0)) / 2.0;

}  // namespace

float frame_contrast_threshold(const ImageView& image, std::span<const ScanRow> rows, float min_contrast,
                               float levels_per_grey) {
  // The measure in 8-bit grey levels: luma plus yellowness (colour) reaches 510.
  std::array<int, 512> levels{};
  int samples = 0;
  double differences = 0.0;
  for (std::size_t r = 0; r < rows.size(); r += kRowStep) {
    const ScanRow& row = rows[r];
    const int x_end = std::min(image.width, row.x_end) - 1;  // each sample and its right neighbour
    for (int x = std::max(0, row.x_begin); x < x_end; x += kPixelStep) {
      const int v = paint_measure_at(image, x, row.y);
      const int d = std::abs(paint_measure_at(image, x + 1, row.y) - v);
      const auto grey = static_cast<int>(static_cast<float>(v) / levels_per_grey);
      ++levels[static_cast<std::size_t>(std::clamp(grey, 0, 511))];
      differences +=
          std::min(static_cast<double>(d) / static_cast<double>(levels_per_grey), static_cast<double>(kMaxNoiseStep));
      ++samples;
    }
  }
  const float configured = min_contrast * levels_per_grey;
  if (samples == 0) return configured;
  int below = 0, median = 0;
  while (median < 511 && 2 * (below += levels[static_cast<std::size_t>(median)]) < samples) ++median;
  const double noise = kSigmaPerMeanDifference * differences / samples;
  const double share = std::clamp(
      std::max(median / kDaylightRoadLevel, kThresholdNoiseSigmas * noise / static_cast<double>(min_contrast)),
      kMinThresholdShare, 1.0);
  return configured * static_cast<float>(share);
}

}  // namespace ccdlane
