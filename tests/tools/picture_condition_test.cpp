// Pictures as another camera or light would give them, against what each alteration does
// to a known picture: a flat grey's level, a step's 10-90 % rise, the noise's spread.
#include "tools/ccdlane/picture_condition.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "core/geometry/camera_model.hpp"

namespace ccdlane::cli {
namespace {

struct Picture {
  int width, height, channels;
  std::vector<std::uint8_t> pixels;
  Picture(int w, int h, int c, std::uint8_t level)
      : width(w), height(h), channels(c), pixels(static_cast<std::size_t>(w * h * c), level) {}
  ImageView view(PixelFormat f = PixelFormat::mono8) const {
    return {pixels.data(), width, height, width * channels, f, 8};
  }
};

std::string parse_error(const std::string& spec) {
  try {
    parse_picture_condition(spec);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(PictureCondition, ParsesEachKeyAndNamesWhatIsWrong) {
  EXPECT_TRUE(parse_picture_condition("").identity());
  EXPECT_EQ(parse_picture_condition("noise=3,blur=1.5,light=0.3"), (PictureCondition{1.5, 0.3, 3.0}));
  EXPECT_EQ(parse_error("fog=1"),
            "fog=1: unknown key fog (scale, blur, light, noise, shade, shade_top, shade_bottom, "
            "dapple, dapple_cover, jpeg)");
  EXPECT_EQ(parse_error("blur=x"), "blur=x: not a number");
  EXPECT_EQ(parse_error("blur=1px"), "blur=1px: not a number");
  EXPECT_EQ(parse_error("light"),
            "light: not key=value (scale=TIMES, blur=PX, light=SHARE, noise=LEVELS, shade=SHARE, dapple=SHARE, "
            "jpeg=QUALITY)");
  EXPECT_EQ(parse_error("jpeg=0"), "jpeg=0: outside [1, 100]");
  EXPECT_EQ(parse_error("jpeg=101"), "jpeg=101: outside [1, 100]");
  EXPECT_EQ(parse_picture_condition("jpeg=75").jpeg, 75.0);
  EXPECT_FALSE(parse_picture_condition("jpeg=75").identity());
  EXPECT_EQ(parse_error("scale=5"), "scale=5: outside [0.25, 4]");
  EXPECT_EQ(parse_picture_condition("scale=1.5").scale, 1.5);
  EXPECT_FALSE(parse_picture_condition("scale=1.5").identity());
  EXPECT_EQ(parse_error("light=0"), "light=0: outside (0, 4]");
  EXPECT_EQ(parse_error("noise=-1"), "noise=-1: outside [0, 20]");
  EXPECT_EQ(parse_error("blur=25"), "blur=25: outside [0, 20]");
  EXPECT_EQ(parse_error("shade=0"), "shade=0: outside (0, 1]");
  EXPECT_EQ(parse_error("shade=0.3,shade_top=0.8"),
            "shade=0.3,shade_top=0.8: shade_top must lie above shade_bottom (shares of the height from the top)");
  const PictureCondition shaded = parse_picture_condition("shade=0.3,shade_top=0.2,shade_bottom=0.4");
  EXPECT_EQ(shaded.shade, 0.3);
  EXPECT_EQ(shaded.shade_top, 0.2);
  EXPECT_EQ(shaded.shade_bottom, 0.4);
  EXPECT_FALSE(shaded.identity());
}

// A bridge's shadow: the rows between the band's edges get the shade's share of the
// light, the rows beyond them all of it, and the penumbra (1 % of the height, centred on
// each edge) a share in between that falls monotonically into the shadow.
TEST(PictureCondition, ShadeDarkensItsBandOfRowsWithSoftEdges) {
  const Picture p(4, 200, 1, 200);
  PictureConditioner c(parse_picture_condition("shade=0.25,shade_top=0.5,shade_bottom=0.75"));
  const ImageView s = c.apply(p.view(), 0);
  EXPECT_EQ(s.row(10)[0], 200);
  EXPECT_EQ(s.row(98)[2], 200);  // above the top edge's penumbra (rows 99-100)
  EXPECT_EQ(s.row(102)[1], 50);  // inside
  EXPECT_EQ(s.row(147)[3], 50);
  EXPECT_EQ(s.row(152)[0], 200);  // below the bottom edge's penumbra (rows 149-150)
  EXPECT_EQ(s.row(199)[0], 200);
  // Row 99's centre lies half a penumbra's half above the edge: a quarter of the way in.
  EXPECT_EQ(s.row(99)[0], 162);  // 200 x (1 - 0.25 x 0.75) = 162.5, rounded to the even level
  EXPECT_EQ(s.row(100)[0], 88);  // three quarters in: 200 x (1 - 0.75 x 0.75) = 87.5, to the even level
}

// Trees' shadows: the upper half of the picture (sky, crowns) keeps its light; below the
// fade, every pixel is in sun (its level), in shadow (the dapple's share of it) or on a
// penumbra between, the shadows covering about dapple_cover of the road; the next frame
// has the same shadows 1 % of the height (and a row) further down, as a car driving on
// under the same trees sees them.
TEST(PictureCondition, DappleLaysTreesShadowsOnTheRoadThatDriftDownFrameByFrame) {
  const Picture p(1280, 720, 1, 200);
  EXPECT_EQ(parse_error("dapple=0"), "dapple=0: outside (0, 1]");
  EXPECT_EQ(parse_error("dapple=0.4,dapple_cover=1"), "dapple_cover=1: outside [0.05, 0.95]");
  PictureConditioner c(parse_picture_condition("dapple=0.4,dapple_cover=0.4"));
  const ImageView first = c.apply(p.view(), 0);
  const std::vector<std::uint8_t> frame0(first.data, first.data + 1280 * 720);
  int shaded = 0, sunny = 0, between = 0;
  for (int y = 0; y < 720; ++y)
    for (int x = 0; x < 1280; ++x) {
      const int v = frame0[static_cast<std::size_t>(y * 1280 + x)];
      if (y < 360) {
        ASSERT_EQ(v, 200) << x << "," << y;
        continue;
      }
      ASSERT_GE(v, 80) << x << "," << y;
      ASSERT_LE(v, 200) << x << "," << y;
      if (y < 404) continue;  // the fade, 6 % of the height
      shaded += v == 80;
      sunny += v == 200;
      between += v != 80 && v != 200;
    }
  const double road = 1280.0 * (720 - 404);
  EXPECT_GT(shaded / road, 0.2) << "shadows cover about 0.4 of the road";
  EXPECT_LT(shaded / road, 0.6);
  EXPECT_GT(sunny / road, 0.3);
  EXPECT_LT(between, shaded) << "soft edges about cores of shadow, not a haze";
  EXPECT_LT(between, sunny);
  const ImageView second = c.apply(p.view(), 1);
  for (int y = 404; y + 8 < 720; ++y)  // round(0.01 x 720) + 1 = 8 rows a frame
    for (int x = 0; x < 1280; ++x)
      ASSERT_EQ(second.row(y + 8)[x], frame0[static_cast<std::size_t>(y * 1280 + x)]) << x << "," << y;
  // The shadows go round a stretch three pictures tall without a seam: on frame 60 its
  // end passes row 480 (60 x 8), which differs from the row above no more than rows do
  // elsewhere on the road.
  const ImageView round = c.apply(p.view(), 60);
  const auto row_change = [&](int y) {
    double sum = 0.0;
    for (int x = 0; x < 1280; ++x) sum += std::abs(round.row(y)[x] - round.row(y - 1)[x]);
    return sum / 1280.0;
  };
  double largest_elsewhere = 0.0;
  for (int y = 405; y < 720; ++y)
    if (std::abs(y - 480) > 2) largest_elsewhere = std::max(largest_elsewhere, row_change(y));
  EXPECT_LE(row_change(480), largest_elsewhere);
}

// Another camera's pixel count: a bright stripe over columns 100-109 of a 400x300
// picture lies over columns 50-54 at half the pixels and 150-164 at 1.5 times, at its
// level (area-averaged or interpolated, not rung), and the camera that takes such
// pictures sees every road point where the resize puts its pixel, distortion and all.
TEST(PictureCondition, ScaleIsACameraOfOtherPixelsOnTheSameChipBehindTheSameLens) {
  Picture p(400, 300, 1, 40);
  for (int y = 0; y < 300; ++y)
    for (int x = 100; x < 110; ++x) p.pixels[static_cast<std::size_t>(y * 400 + x)] = 200;
  for (const double scale : {0.5, 1.5}) {
    PictureCondition condition;
    condition.scale = scale;
    PictureConditioner c(condition);
    const ImageView s = c.apply(p.view(), 0);
    ASSERT_EQ(s.width, static_cast<int>(400 * scale)) << scale;
    ASSERT_EQ(s.height, static_cast<int>(300 * scale)) << scale;
    const int first = static_cast<int>(100 * scale), last = static_cast<int>(110 * scale) - 1;
    const int row = s.height / 2;
    EXPECT_EQ(s.row(row)[first - 2], 40) << scale;
    EXPECT_EQ(s.row(row)[(first + last) / 2], 200) << scale;
    EXPECT_EQ(s.row(row)[last + 2], 40) << scale;
    for (int x = 0; x < s.width; ++x) {  // no level beyond the picture's own: no ringing
      EXPECT_GE(s.row(row)[x], 40) << scale << " column " << x;
      EXPECT_LE(s.row(row)[x], 200) << scale << " column " << x;
    }
  }
  CameraSpec camera;  // the reference camera, its distortion and its principal point off centre
  camera.k_px2 = -8.3e-7;
  camera.cx = 397.25;
  camera.cy = 305.5;
  CameraPose pose;
  pose.f_mm = 5.05;
  pose.H_mm = 1300.0;
  pose.attitude.theta = 0.03;
  pose.attitude.psi = 0.01;
  for (const double scale : {0.5, 1.5, 2.0}) {
    PictureCondition condition;
    condition.scale = scale;
    const CameraSpec taking = camera_taking(condition, camera);
    EXPECT_EQ(taking.Nu, static_cast<int>(camera.Nu * scale));
    EXPECT_NEAR(taking.pitch_u(), camera.pitch_u() / scale, 1e-12);
    EXPECT_NEAR(taking.pitch_v(), camera.pitch_v() / scale, 1e-12);
    const CameraModel recorded(camera, pose), taken(taking, pose);
    for (const Vec3& point : {Vec3(6000.0, 3000.0, 0.0), Vec3(12000.0, -1800.0, 0.0), Vec3(40000.0, 0.0, 0.0)}) {
      const auto a = recorded.pixel_from_point(point), b = taken.pixel_from_point(point);
      ASSERT_TRUE(a && b);
      EXPECT_NEAR(b->x(), (a->x() - 0.5) * scale + 0.5, 1e-6) << scale;
      EXPECT_NEAR(b->y(), (a->y() - 0.5) * scale + 0.5, 1e-6) << scale;
    }
  }
}

TEST(PictureCondition, TheIdentityIsThePictureItself) {
  const Picture p(16, 8, 1, 77);
  PictureConditioner c(parse_picture_condition("light=1"));
  EXPECT_EQ(c.apply(p.view(), 0).data, p.pixels.data());
}

TEST(PictureCondition, LightScalesEveryLevelAndClipsAtWhite) {
  Picture p(8, 4, 3, 0);
  for (std::size_t i = 0; i < p.pixels.size(); i += 3) p.pixels[i] = 200, p.pixels[i + 1] = 100, p.pixels[i + 2] = 51;
  PictureConditioner half(PictureCondition{0.0, 0.5, 0.0});
  const ImageView h = half.apply(p.view(PixelFormat::rgb8), 0);
  EXPECT_EQ(h.format, PixelFormat::rgb8);
  EXPECT_EQ(h.row(3)[21], 100);
  EXPECT_EQ(h.row(3)[22], 50);
  EXPECT_EQ(h.row(3)[23], 26);  // 25.5, rounded to the even level
  PictureConditioner bright(PictureCondition{0.0, 4.0, 0.0});
  const ImageView b = bright.apply(p.view(PixelFormat::rgb8), 0);
  EXPECT_EQ(b.row(0)[0], 255);
  EXPECT_EQ(b.row(0)[2], 204);
  // A 12-bit frame clips at its own white, 4095.
  std::vector<std::uint16_t> deep(16, 3000);
  const ImageView d{reinterpret_cast<const std::uint8_t*>(deep.data()), 4, 4, 8, PixelFormat::mono16, 12};
  const ImageView dd = bright.apply(d, 0);
  EXPECT_EQ(reinterpret_cast<const std::uint16_t*>(dd.row(2))[1], 4095);
}

// A Gaussian of sigma s turns a sharp step into an error function whose 10-90 % rise is
// 2 * 1.2816 s wide.
TEST(PictureCondition, BlurSpreadsAStepAsAGaussianOfItsSigma) {
  for (const double sigma : {1.0, 2.0, 4.0}) {
    Picture p(200, 20, 1, 40);
    for (int y = 0; y < p.height; ++y)
      for (int x = 100; x < p.width; ++x) p.pixels[static_cast<std::size_t>(y * p.width + x)] = 240;
    PictureConditioner c(PictureCondition{sigma, 1.0, 0.0});
    const ImageView b = c.apply(p.view(), 0);
    const std::uint8_t* row = b.row(10);
    // Where the row crosses a level, by linear interpolation between pixel centres.
    auto crossing = [&](double level) {
      for (int x = 1; x < b.width; ++x)
        if (row[x] >= level && row[x - 1] < level) return x - 1 + (level - row[x - 1]) / (row[x] - row[x - 1]);
      return -1.0;
    };
    const double rise = crossing(40 + 0.9 * 200) - crossing(40 + 0.1 * 200);
    // Rounding to levels and interpolating between pixels move each crossing by up to
    // half a pixel at the sharpest.
    EXPECT_NEAR(rise, 2.0 * 1.2816 * sigma, 0.5) << "sigma " << sigma;
  }
}

TEST(PictureCondition, NoiseHasItsSigmaAndIsEachFramesOwnButRepeatable) {
  const Picture p(256, 256, 1, 128);
  PictureConditioner c(PictureCondition{0.0, 1.0, 4.0});
  auto stats = [](const ImageView& v, double& mean, double& sd) {
    double s = 0, ss = 0;
    const double n = static_cast<double>(v.width) * v.height;
    for (int y = 0; y < v.height; ++y)
      for (int x = 0; x < v.width; ++x) s += v.row(y)[x], ss += v.row(y)[x] * static_cast<double>(v.row(y)[x]);
    mean = s / n;
    sd = std::sqrt(ss / n - mean * mean);
  };
  double mean = 0, sd = 0;
  const ImageView f0 = c.apply(p.view(), 0);
  const std::vector<std::uint8_t> first(f0.data, f0.data + 256 * 256);
  stats(f0, mean, sd);
  // 65536 samples: the mean within 4 of its standard errors (4 / 256), the sd within 4 of
  // its own (4 / sqrt(2 * 65536)); rounding to levels adds 1/12 to the variance.
  EXPECT_NEAR(mean, 128.0, 4 * 4.0 / 256);
  EXPECT_NEAR(sd, std::sqrt(16.0 + 1.0 / 12), 4 * 4.0 / std::sqrt(2.0 * 65536));
  EXPECT_EQ(std::vector<std::uint8_t>(c.apply(p.view(), 0).data, c.apply(p.view(), 0).data + 256 * 256), first);
  const ImageView f1 = c.apply(p.view(), 1);
  EXPECT_NE(std::vector<std::uint8_t>(f1.data, f1.data + 256 * 256), first);
}

// A grey picture of a smooth ramp with a bright bar on it (a lane mark), its bar's edges
// off the 8x8 blocks.
Picture ramp_with_bar() {
  Picture p(96, 64, 1, 0);
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x)
      p.pixels[static_cast<std::size_t>(y * p.width + x)] =
          static_cast<std::uint8_t>(x >= 43 && x < 53 ? 200 : 60 + x + y / 2);
  return p;
}

// The root mean square difference of two pictures' levels.
double rms_difference(const ImageView& a, const Picture& b) {
  double sum2 = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width * b.channels; ++x) {
      const double d = a.row(y)[x] - b.pixels[static_cast<std::size_t>(y * a.width * b.channels + x)];
      sum2 += d * d;
    }
  return std::sqrt(sum2 / (static_cast<double>(a.width) * a.height * b.channels));
}

// Through libjpeg and back: the lower the quality, the farther from the picture, and the
// more the steps between the 8x8 blocks stand out from the steps within them on a
// smooth ramp (JPEG's blocks); at quality 100 a grey picture keeps its levels to a few.
// Repeatable; 16-bit frames are refused.
TEST(PictureCondition, JpegIsThePictureThroughAnEncoderAtThatQuality) {
  const Picture p = ramp_with_bar();
  std::vector<double> errors;
  for (const double quality : {100.0, 75.0, 30.0, 5.0}) {
    PictureCondition condition;
    condition.jpeg = quality;
    PictureConditioner c(condition);
    const ImageView out = c.apply(p.view(), 0);
    ASSERT_EQ(out.width, p.width);
    ASSERT_EQ(out.format, PixelFormat::mono8);
    errors.push_back(rms_difference(out, p));
    const std::vector<std::uint8_t> first(out.data, out.data + p.pixels.size());
    EXPECT_EQ(std::vector<std::uint8_t>(c.apply(p.view(), 7).data, c.apply(p.view(), 7).data + p.pixels.size()), first)
        << "quality " << quality << ": no noise, the same encoder: the same picture";
    if (quality == 5.0) {
      // On the ramp left of the bar (columns 0-39), the steps across block edges against
      // those within blocks: a ramp rises by one level a column either way.
      double across = 0.0, within = 0.0;
      int n_across = 0, n_within = 0;
      for (int y = 0; y < p.height; ++y)
        for (int x = 1; x < 40; ++x) {
          const double step = std::abs(out.row(y)[x] - out.row(y)[x - 1]);
          (x % 8 == 0 ? across : within) += step;
          ++(x % 8 == 0 ? n_across : n_within);
        }
      EXPECT_GT(across / n_across, 2.0 * within / n_within) << "blocks";
    }
  }
  EXPECT_LT(errors[0], 1.5) << "quality 100";
  for (std::size_t k = 1; k < errors.size(); ++k) EXPECT_GT(errors[k], errors[k - 1]) << "quality step " << k;
  std::vector<std::uint16_t> deep(64 * 64, 1000);
  const ImageView d{reinterpret_cast<const std::uint8_t*>(deep.data()), 64, 64, 128, PixelFormat::mono16, 12};
  PictureConditioner c(parse_picture_condition("jpeg=75"));
  EXPECT_THROW(c.apply(d, 0), std::invalid_argument);
}

// Colour goes through as colour, whichever order its bytes are in: a BGR frame comes back
// as the RGB frame of the same picture does, its bytes in its own order.
TEST(PictureCondition, JpegKeepsAColourFramesByteOrder) {
  Picture rgb(64, 48, 3, 0), bgr(64, 48, 3, 0);
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x) {
      const std::size_t i = static_cast<std::size_t>((y * rgb.width + x) * 3);
      const std::uint8_t r = static_cast<std::uint8_t>(x < 32 ? 210 : 90), g = static_cast<std::uint8_t>(170),
                         b = static_cast<std::uint8_t>(40 + y);
      rgb.pixels[i] = r, rgb.pixels[i + 1] = g, rgb.pixels[i + 2] = b;
      bgr.pixels[i] = b, bgr.pixels[i + 1] = g, bgr.pixels[i + 2] = r;
    }
  PictureConditioner a(parse_picture_condition("jpeg=90")), b(parse_picture_condition("jpeg=90"));
  const ImageView from_rgb = a.apply(rgb.view(PixelFormat::rgb8), 0);
  const ImageView from_bgr = b.apply(bgr.view(PixelFormat::bgr8), 0);
  ASSERT_EQ(from_bgr.format, PixelFormat::bgr8);
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(from_bgr.row(y)[3 * x + k], from_rgb.row(y)[3 * x + 2 - k]) << x << "," << y << " channel " << k;
  // Away from the colour edge (column 32, whose chroma is shared by two columns), the
  // flat colours keep their levels to a few.
  EXPECT_NEAR(from_rgb.row(20)[3 * 10], 210, 6);
  EXPECT_NEAR(from_rgb.row(20)[3 * 50], 90, 6);
  EXPECT_NEAR(from_rgb.row(20)[3 * 50 + 1], 170, 6);
}

}  // namespace
}  // namespace ccdlane::cli
