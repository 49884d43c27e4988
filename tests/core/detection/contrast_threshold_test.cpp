// The contrast threshold: as configured on a daylight road, in proportion to the road's
// level on a dim one, held above the picture's noise, and never below its floor; for the
// frame, and lower on a band of rows in a shadow across the road.
#include "core/detection/contrast_threshold.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

constexpr int kFlatWidth = 640, kFlatHeight = 200;
constexpr float kConfiguredContrast = 10.0f;

// A flat grey picture at `level` with Gaussian noise `sigma` (8-bit), and every other row
// planned as a scan row across its whole width.
struct FlatRoad {
  std::vector<std::uint8_t> px;
  std::vector<ScanRow> rows;
  ImageView view;

  FlatRoad(double level, double sigma, std::uint32_t seed = 3) : px(kFlatWidth * kFlatHeight) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    for (std::uint8_t& p : px) p = static_cast<std::uint8_t>(std::clamp(std::lround(level + sigma * n(rng)), 0L, 255L));
    for (int y = 0; y < kFlatHeight; y += 2) {
      ScanRow r;
      r.y = y;
      r.x_begin = 0;
      r.x_end = kFlatWidth;
      rows.push_back(r);
    }
    view = {px.data(), kFlatWidth, kFlatHeight, kFlatWidth, PixelFormat::mono8, 8};
  }
  float threshold() const { return frame_contrast_threshold(view, rows, kConfiguredContrast, 1.0f); }
};

TEST(FrameContrastThreshold, ADaylightRoadKeepsTheConfiguredContrast) {
  EXPECT_FLOAT_EQ(FlatRoad(kDaylightRoadLevel + 30.0, 1.0).threshold(), kConfiguredContrast);
  EXPECT_FLOAT_EQ(FlatRoad(200.0, 0.5).threshold(), kConfiguredContrast);
}

TEST(FrameContrastThreshold, ADimRoadLowersItInProportionToTheRoadsLevel) {
  // Clean enough that the noise does not hold it up (6 x 0.2 = 1.2 levels): half a
  // daylight road's level is half the contrast. The median of rounded levels is the
  // level, to half a level (0.06 of the contrast at 85).
  EXPECT_NEAR(FlatRoad(std::round(0.5 * kDaylightRoadLevel), 0.2).threshold(), 0.5f * kConfiguredContrast, 0.1f);
  EXPECT_NEAR(FlatRoad(std::round(0.7 * kDaylightRoadLevel), 0.2).threshold(), 0.7f * kConfiguredContrast, 0.1f);
}

// Paint on pale concrete (TuSimple's at 92-128 levels) that stands 40 % above the
// configured contrast in daylight stands above the threshold still when the camera gets
// half the light: its contrast halves with the road's level, and so must the threshold,
// near enough. So for concrete up to 2 x 0.7 x 85 = 119 levels; on brighter concrete
// with half the light (at 70 levels, up to 98) the threshold keeps more than 0.7.
TEST(FrameContrastThreshold, HalfTheLightOnPaleConcreteKeepsFaintPaint) {
  for (const double concrete : {92.0, 105.0, 118.0}) {
    const float paint = 1.4f * kConfiguredContrast;
    ASSERT_LT(FlatRoad(concrete, 1.0).threshold(), paint);
    EXPECT_LT(FlatRoad(0.5 * concrete, 0.5).threshold(), 0.5f * paint) << concrete;
  }
}

TEST(FrameContrastThreshold, NoiseHoldsItUp) {
  // At 35 the level alone says 35 / 85 x 10 = 4.1; noise of 1.2 levels (its estimate from
  // rounded pixels within a few per cent) says 6 x 1.2 = 7.2.
  EXPECT_NEAR(FlatRoad(35.0, 1.2).threshold(), static_cast<float>(kThresholdNoiseSigmas * 1.2), 0.4f);
  // Noise beyond daylight's margin never raises it above the configured contrast.
  EXPECT_FLOAT_EQ(FlatRoad(35.0, 3.0).threshold(), kConfiguredContrast);
}

TEST(FrameContrastThreshold, ADarkCleanPictureStopsAtTheFloor) {
  EXPECT_FLOAT_EQ(FlatRoad(8.0, 0.0).threshold(), static_cast<float>(kMinThresholdShare) * kConfiguredContrast);
}

TEST(FrameContrastThreshold, SixteenBitLevelsScaleWithTheirDepth) {
  // The same dim road at 12 bits: measure levels per grey level 4095 / 255.
  const FlatRoad grey(35.0, 0.2);
  std::vector<std::uint16_t> px16(grey.px.size());
  const float per_grey = 4095.0f / 255.0f;
  for (std::size_t i = 0; i < px16.size(); ++i)
    px16[i] = static_cast<std::uint16_t>(std::lround(grey.px[i] * static_cast<double>(per_grey)));
  const ImageView v16{reinterpret_cast<const std::uint8_t*>(px16.data()),
                      kFlatWidth,
                      kFlatHeight,
                      2 * kFlatWidth,
                      PixelFormat::mono16,
                      12};
  EXPECT_NEAR(frame_contrast_threshold(v16, grey.rows, kConfiguredContrast, per_grey) / per_grey, grey.threshold(),
              0.2f);
}

// Bands down the picture (contrast_thresholds): rows y0..y1 of `road` replaced by a
// shadow at `level` with noise `sigma`, or by a dark car's back over columns x0..x1.
void shade_rows(FlatRoad& road, int y0, int y1, double level, double sigma, std::uint32_t seed = 5) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < kFlatWidth; ++x)
      road.px[static_cast<std::size_t>(y * kFlatWidth + x)] =
          static_cast<std::uint8_t>(std::clamp(std::lround(level + sigma * n(rng)), 0L, 255L));
}

std::vector<float> row_thresholds(const FlatRoad& road, float& frame) {
  std::vector<float> t(road.rows.size());
  frame = contrast_thresholds(road.view, road.rows, kConfiguredContrast, 1.0f, t);
  return t;
}

// A bridge's shadow across a daylight road: the paint in it stands above its road by the
// shadow's share of daylight's contrast, and its texture is as much fainter. The shadow's
// rows (a whole band of scan rows) get the threshold of a road at its level and noise;
// the daylit rows keep the configured contrast, and so does the frame (its median is
// daylight's).
TEST(BandContrastThreshold, AShadowAcrossTheRoadLowersItsOwnRows) {
  FlatRoad road(110.0, 1.0);
  const int shadow_top = 2 * 3 * kBandRows, shadow_bottom = shadow_top + 2 * 2 * kBandRows;  // scan rows 24-39
  shade_rows(road, shadow_top, shadow_bottom, 35.0, 0.3);
  float frame = 0.0f;
  const std::vector<float> t = row_thresholds(road, frame);
  EXPECT_FLOAT_EQ(frame, kConfiguredContrast);
  // Its upper quartile is 35 levels to within a rounded level: 35 / 85 of the contrast
  // (noise 6 x 0.3 = 1.8 levels says less).
  const float shadow = static_cast<float>(35.0 / kDaylightRoadLevel) * kConfiguredContrast;
  for (std::size_t r = 0; r < t.size(); ++r) {
    const bool in_shadow = road.rows[r].y >= shadow_top && road.rows[r].y < shadow_bottom;
    if (in_shadow)
      EXPECT_NEAR(t[r], shadow, 0.15f) << "row " << road.rows[r].y;
    else
      EXPECT_FLOAT_EQ(t[r], kConfiguredContrast) << "row " << road.rows[r].y;
  }
}

// A dark car's back across more than half of a band's road (far off, the road within
// reach is a few hundred pixels wide) is no shadow on the road: the band's level is its
// upper quartile, the road beside the car (its median would be the car's), and the band
// keeps the frame's.
TEST(BandContrastThreshold, ACarsBackOverMostOfABandIsNoShadow) {
  FlatRoad road(110.0, 1.0);
  for (int y = 0; y < 2 * kBandRows; ++y)
    for (int x = kFlatWidth / 5; x < 4 * kFlatWidth / 5; ++x)
      road.px[static_cast<std::size_t>(y * kFlatWidth + x)] = 25;
  float frame = 0.0f;
  const std::vector<float> t = row_thresholds(road, frame);
  EXPECT_FLOAT_EQ(frame, kConfiguredContrast);
  for (std::size_t r = 0; r < t.size(); ++r) EXPECT_FLOAT_EQ(t[r], kConfiguredContrast) << "row " << road.rows[r].y;
}

// A band brighter than a dim frame (pale concrete under a dusk sky) keeps the frame's
// threshold: a band only ever lowers it, so a dim picture's faint paint is not lost on
// its brighter rows.
TEST(BandContrastThreshold, ABrightBandInADimPictureKeepsTheFramesThreshold) {
  FlatRoad road(35.0, 0.2);
  shade_rows(road, 0, 2 * kBandRows, 80.0, 0.2);
  float frame = 0.0f;
  const std::vector<float> t = row_thresholds(road, frame);
  EXPECT_NEAR(frame, static_cast<float>(35.0 / kDaylightRoadLevel) * kConfiguredContrast, 0.1f);
  for (std::size_t r = 0; r < t.size(); ++r) EXPECT_FLOAT_EQ(t[r], frame) << "row " << road.rows[r].y;
}

TEST(FrameContrastThreshold, NoRowsKeepTheConfiguredContrast) {
  const FlatRoad road(20.0, 0.2);
  EXPECT_FLOAT_EQ(frame_contrast_threshold(road.view, {}, kConfiguredContrast, 1.0f), kConfiguredContrast);
}

}  // namespace
}  // namespace ccdlane
