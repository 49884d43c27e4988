// The renderer against the camera model: lane marks appear where projecting the truth
// lines puts them (to a few hundredths of a pixel), the sky is above the horizon, noise
// has the configured sigma, 16-bit frames scale, colour scenes (yellow paint on concrete,
// hard shadows, a barrier) look as configured and their grey frames are their luma,
// rendering is deterministic and allocation-free.
#include "core/synth/road_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "core/detection/paint_measure.hpp"
#include "core/geometry/camera_model.hpp"
#include "tests/core/synth/rendered_road.hpp"
#include "tests/core/synth/truth_projection.hpp"
#include "tests/support/allocation_counter.hpp"

namespace ccdlane {
namespace {

Config small_camera() {
  Config c = test::small_reference_camera();
  c.attitude = {0.8, 4.0, -1.5};
  return c;
}

struct Image {
  std::vector<std::uint8_t> px;
  MutableImageView view;
  Image(int w, int h, PixelFormat f = PixelFormat::mono8, int bits = 8)
      : px(static_cast<std::size_t>(w * h * bytes_per_pixel(f))) {
    view = {px.data(), w, h, w * bytes_per_pixel(f), f, bits};
  }
  double at(int x, int y) const { return ImageView(view).at(x, y); }
};

TEST(RoadRenderer, MarksAreWhereTheCameraModelProjectsTheTruth) {
  Config c = small_camera();
  SynthConfig& s = c.synth;
  s.texture_grey = s.noise_sigma = s.gradient = s.shadow_depth = 0.0;
  s.dashed = DashedLines::none;
  s.supersample = 8;
  s.curvature_per_mm = 2e-7;
  const SynthDrive drive(c.synth, c.nominal_pose());
  const SynthFrame f = drive.frame(40);
  RoadRenderer r(c.camera, s);
  Image img(400, 300);
  r.render(f, img.view);
  const CameraModel cam(c.camera, f.pose);
  int checked = 0;
  double worst = 0.0;
  for (int j = 0; j < f.num_lines; ++j) {
    for (int y = 150; y < 300; y += 3) {
      const auto want = test::truth_column(cam, f, j, y + 1.0);
      if (!want || *want < 8 || *want > 392) continue;
      // Paint above the asphalt level, summed across the mark in this row.
      const int x0 = static_cast<int>(*want) - 1;
      const double asphalt = s.asphalt_grey;
      double sum = 0, moment = 0;
      int x = x0;
      while (x > 0 && img.at(x - 1, y) > asphalt + 0.5) --x;
      for (; x < 400 && (img.at(x, y) > asphalt + 0.5 || x <= x0); ++x) {
        const double w = std::max(0.0, img.at(x, y) - asphalt);
        sum += w;
        moment += w * (x + 1);
      }
      if (sum < 2 * (s.paint_grey - asphalt)) continue;  // a mark narrower than 2 px: centroid too coarse
      const double got = moment / sum;
      worst = std::max(worst, std::abs(got - *want));
      EXPECT_NEAR(got, *want, 0.05) << "line " << j << " row " << y + 1;
      ++checked;
    }
  }
  EXPECT_GT(checked, 60);
  RecordProperty("worst_centroid_error_px", std::to_string(worst));
}

TEST(RoadRenderer, SkyAboveTheHorizonRoadBelow) {
  Config c = small_camera();
  c.synth.noise_sigma = 0;
  const SynthDrive drive(c.synth, c.nominal_pose());
  const SynthFrame f = drive.frame(0);
  RoadRenderer r(c.camera, c.synth);
  Image img(400, 300);
  r.render(f, img.view);
  const CameraModel cam(c.camera, f.pose);
  // Top row: sky (brighter than any asphalt); bottom centre: asphalt.
  for (int x = 0; x < 400; x += 10) EXPECT_GT(img.at(x, 0), c.synth.asphalt_grey + 40) << x;
  EXPECT_NEAR(img.at(200, 290), c.synth.asphalt_grey, 3 * c.synth.texture_grey);
  // Rows whose centre pixel has no ground point are not road.
  for (int y = 0; y < 300; ++y) {
    if (cam.ground_point_from_pixel(Vec2(201, y + 1))) break;
    EXPECT_GT(img.at(200, y), 0.7 * c.synth.verge_grey) << y;
  }
}

TEST(RoadRenderer, SensorNoiseHasTheConfiguredSigma) {
  Config c = small_camera();
  c.synth.noise_sigma = 3.0;
  const SynthDrive drive(c.synth, c.nominal_pose());
  SynthFrame a = drive.frame(5), b = a;
  b.index = 6;  // same scene, another frame's noise
  RoadRenderer r(c.camera, c.synth);
  Image ia(400, 300), ib(400, 300);
  r.render(a, ia.view);
  r.render(b, ib.view);
  double sum2 = 0;
  int n = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) {
      const double va = ia.at(x, y), vb = ib.at(x, y);
      if (va < 10 || va > 245) continue;  // clipped
      sum2 += (va - vb) * (va - vb);
      ++n;
    }
  // The difference of two frames: sigma * sqrt(2), plus quantisation (1/12 each).
  EXPECT_NEAR(std::sqrt(sum2 / n), std::sqrt(2 * 9.0 + 2 / 12.0), 0.1);
}

TEST(RoadRenderer, SixteenBitFramesAreTheEightBitScaled) {
  Config c = small_camera();
  c.synth.noise_sigma = 0;
  const SynthDrive drive(c.synth, c.nominal_pose());
  const SynthFrame f = drive.frame(3);
  RoadRenderer r(c.camera, c.synth);
  Image i8(400, 300), i16(400, 300, PixelFormat::mono16, 12);
  r.render(f, i8.view);
  r.render(f, i16.view);
  for (int y = 0; y < 300; y += 7)
    for (int x = 0; x < 400; x += 7) EXPECT_NEAR(i16.at(x, y) * 255.0 / 4095.0, i8.at(x, y), 0.6) << x << "," << y;
}

// At night the low beams light the near road as by day, the road 30 m ahead with a
// sixteenth of that (their inverse square beyond 8 m, a little less off the beam's axis),
// the sky not at all; retroreflective paint stands above the road by four times its
// daylight share, so that far away it still stands out where the road is near black.
TEST(RoadRenderer, AtNightTheBeamsLightTheNearRoadAndThePaintShinesBack) {
  Config c = small_camera();
  c.attitude = {0.0, 4.0, 0.0};
  SynthConfig& s = c.synth;
  s.noise_sigma = s.gradient = s.texture_grey = 0.0;
  s.dashed = DashedLines::none;
  s.weave_mm = 0.0;
  const SynthDrive drive(s, c.nominal_pose());
  const SynthFrame f = drive.frame(0);
  const CameraModel cam(c.camera, f.pose);
  Image day(400, 300), night(400, 300);
  RoadRenderer(c.camera, s).render(f, day.view);
  s.night = true;
  RoadRenderer(c.camera, s).render(f, night.view);
  // The road's own level halfway between the own lane's lines, and the paint's on its
  // left line, in the picture's row at distance X ahead.
  const auto levels = [&](const Image& img, double X_mm) {
    const Vec2 centre = *cam.pixel_from_point(Vec3(X_mm, 0.5 * (f.y0_mm[1] + f.y0_mm[2]), 0.0));
    const Vec2 line = *cam.pixel_from_point(Vec3(X_mm, f.y0_mm[1], 0.0));
    const int y = static_cast<int>(std::lround(centre.y())) - 1;  // 1-based pixels to 0-based
    double paint = 0.0;
    for (int x = static_cast<int>(line.x()) - 3; x <= static_cast<int>(line.x()) + 2; ++x)
      paint = std::max(paint, img.at(x, y));
    return std::pair{img.at(static_cast<int>(std::lround(centre.x())) - 1, y), paint};
  };
  const auto [day_near, day_near_paint] = levels(day, 6000.0);
  const auto [night_near, night_near_paint] = levels(night, 6000.0);
  const auto [day_far, day_far_paint] = levels(day, 30000.0);
  const auto [night_far, night_far_paint] = levels(night, 30000.0);
  EXPECT_NEAR(night_near, day_near, 0.1 * day_near) << "the beams light the near road";
  // (8 / 30)^2 of the day's, within what the row's rounding to a pixel (a metre or two
  // nearer or farther) and the beam's spread across make of it, to a grey level.
  EXPECT_LE(night_far, 1.5 * day_far / 16.0 + 1.0) << "an inverse square beyond 8 m";
  EXPECT_GE(night_far, 0.5 * day_far / 16.0 - 1.0);
  EXPECT_GT((night_far_paint - night_far) / night_far, 2.0 * (day_far_paint - day_far) / day_far)
      << "paint shines back";
  EXPECT_EQ(night_near_paint, 255.0) << "near paint saturates, as it does at night";
  EXPECT_LT(night.at(200, 5), 10.0) << "no sky light";
  EXPECT_GT(day.at(200, 5), 150.0);
}

// Cars ahead stand on the road and hide it: the first, in the own lane, shows its body
// where the road ahead of its rear was, its dark underbody band just above the road, and
// red tail lights, lit at night (brighter than the near road) and dull by day.
TEST(RoadRenderer, ACarAheadHidesTheRoadAndShowsItsTailLights) {
  Config c = small_camera();
  c.attitude = {0.0, 4.0, 0.0};
  SynthConfig& s = c.synth;
  s.noise_sigma = s.gradient = s.texture_grey = s.shadow_depth = 0.0;
  s.weave_mm = 0.0;
  s.colour = true;
  const SynthDrive drive(s, c.nominal_pose());
  const SynthFrame f = drive.frame(0);
  const CameraModel cam(c.camera, f.pose);
  Image road(400, 300, PixelFormat::rgb8), day(400, 300, PixelFormat::rgb8), night(400, 300, PixelFormat::rgb8);
  RoadRenderer(c.camera, s).render(f, road.view);
  s.cars = 1;
  RoadRenderer(c.camera, s).render(f, day.view);
  s.night = true;
  RoadRenderer(c.camera, s).render(f, night.view);
  // The first car's rear is at least 15 m ahead, 4.5 m long: the road 17 m ahead in the
  // own lane's middle lies under it whatever its seeded place, 15-21 m.
  const double middle = 0.5 * (f.y0_mm[1] + f.y0_mm[2]);
  const auto pixel = [&](double X, double Y, double Z) {
    const Vec2 p = *cam.pixel_from_point(Vec3(X, Y, Z));
    return std::pair{static_cast<int>(std::lround(p.x())) - 1, static_cast<int>(std::lround(p.y())) - 1};
  };
  const auto red = [](const Image& img, int x, int y) { return img.px[static_cast<std::size_t>(3 * (y * 400 + x))]; };
  const auto green = [](const Image& img, int x, int y) {
    return img.px[static_cast<std::size_t>(3 * (y * 400 + x) + 1)];
  };
  // Just ahead of the rear, 1.2 m up: the body (a different grey from the road's).
  const auto [bx, by] = pixel(21500.0, middle, 1200.0);
  EXPECT_NE(green(day, bx, by), green(road, bx, by)) << "the car hides the road";
  // Far beyond the car, in the own lane at road level: hidden by it too; and a lane
  // line's paint beside the car still there.
  const auto [hx, hy] = pixel(40000.0, middle, 0.0);
  EXPECT_NE(green(day, hx, hy), green(road, hx, hy));
  const auto [lx, ly] = pixel(8000.0, f.y0_mm[1], 0.0);
  EXPECT_EQ(green(day, lx, ly), green(road, lx, ly)) << "the road before the car is the road";
  // A tail light: scan the rows of the rear between 0.75 and 0.95 m up for red.
  int lit_night = 0, lit_day = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) {
      lit_night += red(night, x, y) > 200 && red(night, x, y) > 2 * green(night, x, y);
      lit_day += red(day, x, y) > 100 && red(day, x, y) > 2 * green(day, x, y) && red(day, x, y) < 250;
    }
  EXPECT_GT(lit_night, 0) << "lit tail lights at night";
  EXPECT_GT(lit_day, 0) << "tail lights by day";
}

// A colour scene with every disturbance: yellow left edge on concrete, tree shadows, barrier.
Config colour_road() {
  Config c = small_camera();
  c.attitude = {0.0, 4.0, 0.0};
  SynthConfig& s = c.synth;
  s.colour = s.yellow_left_edge = s.hard_shadows = s.barrier = true;
  s.surface = RoadSurface::concrete;
  s.shadow_depth = 0.5;
  s.lanes = 2;
  s.ego_lane = 0;
  s.weave_mm = 0;
  s.noise_sigma = s.gradient = 0.0;
  return c;
}

TEST(RoadRenderer, YellowPaintOnConcreteStandsOutInColourOnly) {
  Config c = colour_road();
  c.synth.hard_shadows = false;
  c.synth.shadow_depth = 0.0;
  c.synth.texture_grey = 0.0;
  c.synth.dashed = DashedLines::none;
  const SynthDrive drive(c.synth, c.nominal_pose());
  const SynthFrame f = drive.frame(0);
  RoadRenderer r(c.camera, c.synth);
  ASSERT_EQ(r.format(), PixelFormat::rgb8);
  Image img(400, 300, PixelFormat::rgb8);
  r.render(f, img.view);
  const CameraModel cam(c.camera, f.pose);
  int checked = 0;
  for (int y = 200; y < 300; y += 5) {
    const auto yellow = test::truth_column(cam, f, 0, y + 1.0), white = test::truth_column(cam, f, 1, y + 1.0);
    if (!yellow || !white || *yellow < 20) continue;
    const int xy = static_cast<int>(std::lround(*yellow)) - 1, xw = static_cast<int>(std::lround(*white)) - 1;
    const int road = (xy + xw) / 2;
    const ImageView v = img.view;
    // In grey (luma) the yellow line is within a few levels of the concrete, below the
    // detector's default minimum contrast; the paint measure puts it far above.
    EXPECT_LT(std::abs(v.at(xy, y) - v.at(road, y)), 10) << y;
    EXPECT_GT(paint_measure_at(v, xy, y) - paint_measure_at(v, road, y), 60) << y;
    EXPECT_GT(paint_measure_at(v, xw, y) - paint_measure_at(v, road, y), 20) << y;
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(RoadRenderer, GreyFramesOfAColourSceneAreItsLumaTheBarrierStandsLeftAndNothingIsAllocated) {
  const Config c = colour_road();
  const SynthDrive drive(c.synth, c.nominal_pose());
  const SynthFrame f = drive.frame(3);
  RoadRenderer r(c.camera, c.synth);
  Image rgb(400, 300, PixelFormat::rgb8), bgr(400, 300, PixelFormat::bgr8), grey(400, 300);
  {
    test::AllocationScope scope;
    r.render(f, rgb.view);
    EXPECT_EQ(scope.count(), 0u);
  }
  r.render(f, bgr.view);
  r.render(f, grey.view);
  for (int y = 0; y < 300; y += 3)
    for (int x = 0; x < 400; x += 3) {
      EXPECT_NEAR(ImageView(rgb.view).at(x, y), grey.at(x, y), 1.0) << x << "," << y;
      EXPECT_EQ(ImageView(bgr.view).at(x, y), ImageView(rgb.view).at(x, y)) << x << "," << y;
    }
  // The barrier's bright foot: on rows that see the road 10 m ahead, left of the yellow
  // line, some pixel as bright as the foot's concrete.
  const CameraModel cam(c.camera, f.pose);
  const auto p = cam.pixel_from_point(Vec3(10000, f.y0_mm[0] + 700, 0));
  ASSERT_TRUE(p);
  const int y = static_cast<int>(p->y()) - 1;
  double brightest = 0;
  for (int x = std::max(0, static_cast<int>(p->x()) - 30); x < static_cast<int>(p->x()); ++x)
    brightest = std::max<double>(brightest, grey.at(x, y));
  EXPECT_GT(brightest, 200.0);
}

TEST(RoadRenderer, DeterministicPerSeedAndAllocationFree) {
  Config c = small_camera();
  c.synth.blur_px = 0.8;
  const SynthDrive drive(c.synth, c.nominal_pose());
  const SynthFrame f = drive.frame(9);
  RoadRenderer r1(c.camera, c.synth), r2(c.camera, c.synth);
  Image a(400, 300), b(400, 300);
  {
    test::AllocationScope scope;
    r1.render(f, a.view);
    EXPECT_EQ(scope.count(), 0u);
  }
  r2.render(f, b.view);
  EXPECT_EQ(a.px, b.px);
  c.synth.seed = 99;
  RoadRenderer r3(c.camera, c.synth);
  r3.render(f, b.view);
  EXPECT_NE(a.px, b.px);
}

}  // namespace
}  // namespace ccdlane
