// The contrast threshold from the road's level and noise on the scan rows: the frame's
// and each band's.
#include "core/detection/contrast_threshold.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "core/detection/paint_measure.hpp"

namespace ccdlane {
namespace {

// Every second scan row of a band, every 32nd pixel of the row (each row at another
// phase, so that a band's rows do not sample the same columns).
constexpr int kBandRowStep = 2;
constexpr int kPixelStep = 32;
constexpr int kRowPhase = 7;
// A band's samples kept for its quartile (a 1280-wide picture gives up to 160), and the
// fewest that say its level.
constexpr int kMaxBandSamples = 1024;
constexpr int kMinBandSamples = 16;
// A difference larger than this is an edge (paint, a car, a shadow's border), not noise.
constexpr int kMaxNoiseStep = 20;
// The standard deviation of a Gaussian from the mean absolute difference of two of its
// samples: E|a - b| = 2 sigma / sqrt(pi).
const double kSigmaPerMeanDifference = std::sqrt(std::acos(-1.0)) / 2.0;

// The threshold's share of `min_contrast` for a road at `level` grey levels with pixel
// noise `noise` (grey levels).
double threshold_share(double level, double noise, float min_contrast) {
  return std::clamp(
      std::max(level / kDaylightRoadLevel, kThresholdNoiseSigmas * noise / static_cast<double>(min_contrast)),
      kMinThresholdShare, 1.0);
}

}  // namespace

float contrast_thresholds(const ImageView& image, std::span<const ScanRow> rows, float min_contrast,
                          float levels_per_grey, std::span<float> row_thresholds) {
  const bool per_band = row_thresholds.size() >= rows.size();
  const float configured = min_contrast * levels_per_grey;
  // The measure in 8-bit grey levels: luma plus yellowness (colour) reaches 510.
  std::array<int, 512> levels{};
  std::array<int, kMaxBandSamples> band{};
  int samples = 0;
  double differences = 0.0;
  for (std::size_t first = 0; first < rows.size(); first += kBandRows) {
    const std::size_t end = std::min(rows.size(), first + kBandRows);
    int n = 0;
    double band_differences = 0.0;
    for (std::size_t r = first; r < end; r += kBandRowStep) {
      const ScanRow& row = rows[r];
      const int x_end = std::min(image.width, row.x_end) - 1;  // each sample and its right neighbour
      for (int x = std::max(0, row.x_begin) + static_cast<int>(r) * kRowPhase % kPixelStep;
           x < x_end && n < kMaxBandSamples; x += kPixelStep) {
        const int v = paint_measure_at(image, x, row.y);
        const int d = std::abs(paint_measure_at(image, x + 1, row.y) - v);
        band[static_cast<std::size_t>(n++)] = v;
        ++levels[static_cast<std::size_t>(
            std::clamp(static_cast<int>(static_cast<float>(v) / levels_per_grey), 0, 511))];
        band_differences +=
            std::min(static_cast<double>(d) / static_cast<double>(levels_per_grey), static_cast<double>(kMaxNoiseStep));
      }
    }
    samples += n;
    differences += band_differences;
    if (!per_band) continue;
    float t = configured;
    if (n >= kMinBandSamples) {
      const auto q = band.begin() + static_cast<std::ptrdiff_t>(kBandLevelQuantile * n);
      std::nth_element(band.begin(), q, band.begin() + n);
      const double level = static_cast<double>(*q) / static_cast<double>(levels_per_grey);
      t = configured *
          static_cast<float>(threshold_share(level, kSigmaPerMeanDifference * band_differences / n, min_contrast));
    }
    std::fill(row_thresholds.begin() + static_cast<std::ptrdiff_t>(first),
              row_thresholds.begin() + static_cast<std::ptrdiff_t>(end), t);
  }
  float frame = configured;
  if (samples > 0) {
    int below = 0, median = 0;
    while (median < 511 && 2 * (below += levels[static_cast<std::size_t>(median)]) < samples) ++median;
    frame = configured *
            static_cast<float>(threshold_share(median, kSigmaPerMeanDifference * differences / samples, min_contrast));
  }
  if (per_band)
    for (std::size_t r = 0; r < rows.size(); ++r) row_thresholds[r] = std::min(row_thresholds[r], frame);
  return frame;
}

float frame_contrast_threshold(const ImageView& image, std::span<const ScanRow> rows, float min_contrast,
                               float levels_per_grey) {
  return contrast_thresholds(image, rows, min_contrast, levels_per_grey, {});
}

}  // namespace ccdlane
