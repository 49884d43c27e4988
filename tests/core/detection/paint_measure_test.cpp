// The lane-paint measure: its values for the colours of the road (white and yellow
// paint, asphalt, concrete, sky, cars, leaves), the row function against the pixel
// function for every format, and detection on a rendered road whose yellow paint has
// the concrete's luma (invisible in grey) found in colour at the true positions, with
// no allocation per frame.
#include "core/detection/paint_measure.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/lane_detector.hpp"
#include "tests/core/synth/rendered_road.hpp"
#include "tests/core/synth/truth_projection.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

TEST(PaintMeasure, WhiteAndYellowPaintStandAboveAsphaltAndConcrete) {
  const int asphalt = paint_measure8(80, 80, 84), concrete = paint_measure8(172, 170, 162);
  const int white = paint_measure8(235, 235, 235), yellow = paint_measure8(225, 185, 60);
  const int yellow_in_shade = paint_measure8(120, 100, 45), concrete_in_shade = paint_measure8(88, 92, 104);
  EXPECT_EQ(white, 235);  // no chroma: the luma
  EXPECT_GT(yellow - concrete, 60) << "in grey the two differ by " << luma8(225, 185, 60) - luma8(172, 170, 162);
  EXPECT_GT(white - asphalt, 100);
  EXPECT_GT(yellow - asphalt, 100);
  EXPECT_GT(yellow_in_shade - concrete_in_shade, 40);
  // What is not yellow gets no bonus: blue sky and shade, red cars, green leaves.
  EXPECT_EQ(paint_measure8(120, 160, 220), luma8(120, 160, 220));
  EXPECT_EQ(paint_measure8(200, 30, 30), luma8(200, 30, 30));
  EXPECT_EQ(paint_measure8(60, 120, 50), luma8(60, 120, 50) + 10);  // a leaf: min(r, g) - b is small
}

TEST(PaintMeasure, RowsAgreeWithPixelsInEveryFormat) {
  const int w = 7;
  std::vector<std::uint8_t> rgb(3 * w), bgr(3 * w), mono(w);
  std::vector<std::uint16_t> wide(w);
  for (int x = 0; x < w; ++x) {
    const std::uint8_t r = static_cast<std::uint8_t>(30 * x + 20), g = static_cast<std::uint8_t>(200 - 25 * x),
                       b = static_cast<std::uint8_t>(17 * x);
    rgb[3 * x] = bgr[3 * x + 2] = r;
    rgb[3 * x + 1] = bgr[3 * x + 1] = g;
    rgb[3 * x + 2] = bgr[3 * x] = b;
    mono[x] = g;
    wide[x] = static_cast<std::uint16_t>(1000 + 300 * x);
  }
  const ImageView views[] = {
      {rgb.data(), w, 1, 3 * w, PixelFormat::rgb8, 8},
      {bgr.data(), w, 1, 3 * w, PixelFormat::bgr8, 8},
      {mono.data(), w, 1, w, PixelFormat::mono8, 8},
      {reinterpret_cast<const std::uint8_t*>(wide.data()), w, 1, 2 * w, PixelFormat::mono16, 12}};
  for (const ImageView& v : views) {
    std::vector<std::uint16_t> row(w, 0xFFFF);
    paint_measure_row(v, 0, 2, w, row.data());
    EXPECT_EQ(row[1], 0xFFFF) << "outside x0..x1 untouched";
    for (int x = 2; x < w; ++x) EXPECT_EQ(row[x], paint_measure_at(v, x, 0)) << static_cast<int>(v.format) << " " << x;
  }
  for (int x = 0; x < w; ++x) {
    EXPECT_EQ(paint_measure_at(views[0], x, 0), paint_measure_at(views[1], x, 0));
    EXPECT_EQ(paint_measure_at(views[2], x, 0), mono[x]);
    EXPECT_EQ(paint_measure_at(views[3], x, 0), wide[x]);
  }
  EXPECT_EQ(paint_measure_levels_per_grey(views[0]), 1.0f);
  EXPECT_FLOAT_EQ(paint_measure_levels_per_grey(views[3]), 4095.0f / 255.0f);
}

// A row long enough for the vectorised colour loop (built for several instruction sets,
// the CPU's best taken) and its scalar tail, over pixels of every channel value, at
// every start column modulo a vector: the same integers as the pixel function.
TEST(PaintMeasure, LongColourRowsAgreeWithPixelsAtEveryAlignment) {
  const int w = 1280;
  std::vector<std::uint8_t> rgb(3 * w), bgr(3 * w);
  std::uint32_t state = 12345;
  for (int x = 0; x < w; ++x)
    for (int k = 0; k < 3; ++k) {
      state = state * 1664525u + 1013904223u;
      rgb[3 * x + k] = bgr[3 * x + 2 - k] = static_cast<std::uint8_t>(state >> 24);
    }
  rgb[0] = rgb[1] = 255, rgb[2] = 0;  // the largest measure: 255 + 255
  const ImageView views[] = {{rgb.data(), w, 1, 3 * w, PixelFormat::rgb8, 8},
                             {bgr.data(), w, 1, 3 * w, PixelFormat::bgr8, 8}};
  for (const ImageView& v : views)
    for (int x0 = 0; x0 < 33; ++x0) {
      std::vector<std::uint16_t> row(w, 0xFFFF);
      paint_measure_row(v, 0, x0, w - x0 / 2, row.data());
      for (int x = x0; x < w - x0 / 2; ++x) ASSERT_EQ(row[x], paint_measure_at(v, x, 0)) << x0 << " " << x;
      if (x0 > 0) {
        EXPECT_EQ(row[x0 - 1], 0xFFFF);
      }
    }
}

// A concrete road (grey 150) with yellow paint of the concrete's own luma: rendered
// twice from one truth, with the paint bright and with no paint, the difference gives
// each pixel's paint coverage; the colour frame mixes concrete and yellow by it.
struct YellowOnConcrete {
  test::RenderedRoad painted, bare;
  std::vector<std::uint8_t> rgb, grey;
  explicit YellowOnConcrete(const Config& c) : painted(with_paint(c, 250.0)), bare(with_paint(c, 150.0)) {}
  static Config with_paint(Config c, double paint) {
    c.synth.asphalt_grey = 150.0;
    c.synth.paint_grey = paint;
    return c;
  }
  SynthFrame render(std::uint64_t k, PixelFormat format) {
    const SynthFrame f = painted.render(k);
    bare.render(k);
    const std::size_t n = painted.px.size();
    rgb.assign(3 * n, 0);
    grey.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const double road = bare.px[i];
      const double cover = std::clamp((painted.px[i] - road) / std::max(1.0, 250.0 - road), 0.0, 1.0);
      // Yellow whose luma is the concrete's: +25 red, +8 green, -80 blue.
      const double r = road + cover * 25, g = road + cover * 8, b = road - cover * 80;
      auto byte = [](double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
      const std::size_t o = format == PixelFormat::bgr8 ? 2 : 0;
      rgb[3 * i + o] = byte(r);
      rgb[3 * i + 1] = byte(g);
      rgb[3 * i + 2 - o] = byte(b);
      grey[i] = luma8(byte(r), byte(g), byte(b));
    }
    return f;
  }
  ImageView colour(PixelFormat format) const {
    const Config& c = painted.config;
    return {rgb.data(), c.camera.Nu, c.camera.Nv, 3 * c.camera.Nu, format, 8};
  }
  ImageView luma() const {
    const Config& c = painted.config;
    return {grey.data(), c.camera.Nu, c.camera.Nv, c.camera.Nu, PixelFormat::mono8, 8};
  }
};

TEST(PaintMeasure, YellowPaintOnConcreteIsFoundInColourWhereGreyLosesIt) {
  Config c = default_config();
  c.attitude = {0.0, 3.0, 0.0};
  YellowOnConcrete scene(c);
  LaneDetector det(c.camera, c.detection);
  for (PixelFormat format : {PixelFormat::rgb8, PixelFormat::bgr8}) {
    for (std::uint64_t k : {0u, 40u}) {
      const SynthFrame f = scene.render(k, format);
      EXPECT_EQ(det.detect(scene.luma(), f.pose, {}).num_lines, 0) << "the paint's luma is the road's";
      const DetectionResult& r = det.detect(scene.colour(format), f.pose, {});
      ASSERT_EQ(r.num_lines, 4) << "frame " << k;
      const CameraModel cam(c.camera, f.pose);
      // Every pick on its own truth line (lines come left to right, as the truth's).
      double sum2 = 0, worst = 0;
      int n = 0;
      for (const Pick& p : r.picks) {
        const auto want = test::truth_column(cam, f, p.line, p.py);
        if (!want) continue;
        sum2 += (p.px - *want) * (p.px - *want);
        worst = std::max(worst, std::abs(p.px - *want));
        ++n;
      }
      EXPECT_GT(n, 100);
      // The grey test's bounds (lane_detector_test: 0.15 px RMS, 0.8 px worst) with room
      // for the 8-bit rounding of the mixed colour.
      EXPECT_LT(std::sqrt(sum2 / n), 0.25) << "frame " << k;
      EXPECT_LT(worst, 1.2) << "frame " << k;
    }
  }
  // Colour detection allocates nothing per frame either.
  const SynthFrame f = scene.render(3, PixelFormat::rgb8);
  const RoadLine priors[] = {{f.y0_mm[1], 0, 0}, {f.y0_mm[2], 0, 0}};
  test::AllocationScope scope;
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(det.detect(scene.colour(PixelFormat::rgb8), f.pose, priors).num_lines, 4);
    EXPECT_EQ(det.detect(scene.colour(PixelFormat::rgb8), f.pose, {}).num_lines, 4);
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace ccdlane
