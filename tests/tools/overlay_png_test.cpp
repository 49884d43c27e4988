// Overlay pictures: the frame in grey, marks, picks and road lines in their line's colour
// where the camera model puts them, and a PNG that decodes back to the same pixels.
#include "tools/ccdlane/overlay_png.hpp"

#include <png.h>

#include <filesystem>
#include <vector>

#include <gtest/gtest.h>

#include "app/config.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane::cli {
namespace {

bool grey(const std::array<std::uint8_t, 3>& p) { return p[0] == p[1] && p[1] == p[2]; }

TEST(Overlay, DrawsWhereTheCameraModelSays) {
  std::vector<std::uint16_t> frame(800 * 600, 1000);  // 12-bit frame: grey 1000 -> 62
  const ImageView view{reinterpret_cast<const std::uint8_t*>(frame.data()), 800, 600, 1600, PixelFormat::mono16, 12};
  Overlay o(view);
  EXPECT_EQ(o.pixel(10, 10), (std::array<std::uint8_t, 3>{62, 62, 62}));
  const Pick picks[] = {{0, 101.0, 201.0}, {1, 301.0, 401.0}};
  o.draw_picks(picks);
  EXPECT_FALSE(grey(o.pixel(100, 200)));
  EXPECT_FALSE(grey(o.pixel(300, 400)));
  EXPECT_NE(o.pixel(100, 200), o.pixel(300, 400));  // one colour per line
  MarkCandidate m;
  m.left_px = 500;
  m.right_px = 506;
  m.py = 51;
  o.draw_marks({&m, 1});
  EXPECT_EQ(o.pixel(502, 50), (std::array<std::uint8_t, 3>{150, 150, 150}));  // ungrouped: grey ticks
  Config c = default_config();
  c.attitude.theta_deg = 3.0;
  const CameraModel cam(c.camera, c.nominal_pose());
  o.draw_road_line(cam, {-1800.0, 0.0, 0.0}, 5000, 30000, 2);
  const Vec2 at = *cam.pixel_from_point(Vec3(10000, -1800, 0));
  EXPECT_FALSE(grey(o.pixel(static_cast<int>(std::lround(at.x() - 1)), static_cast<int>(std::lround(at.y() - 1)))));
}

TEST(Overlay, PngDecodesToTheSamePixels) {
  test::TempDir dir;
  std::vector<std::uint8_t> frame(64 * 48);
  for (std::size_t i = 0; i < frame.size(); ++i) frame[i] = static_cast<std::uint8_t>(i * 7);
  Overlay o(ImageView{frame.data(), 64, 48, 64, PixelFormat::mono8, 8});
  const Pick p{3, 20, 20};
  o.draw_picks({&p, 1});
  const std::string path = dir.file("o.png");
  o.write_png(path);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  ASSERT_TRUE(png_image_begin_read_from_file(&image, path.c_str()));
  image.format = PNG_FORMAT_RGB;
  std::vector<std::uint8_t> rgb(PNG_IMAGE_SIZE(image));
  ASSERT_TRUE(png_image_finish_read(&image, nullptr, rgb.data(), 0, nullptr));
  ASSERT_EQ(image.width, 64u);
  ASSERT_EQ(image.height, 48u);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(rgb[static_cast<std::size_t>((y * 64 + x) * 3 + k)], o.pixel(x, y)[static_cast<std::size_t>(k)]);
  EXPECT_THROW(o.write_png(dir.file("no/such/dir/o.png")), std::runtime_error);
}

}  // namespace
}  // namespace ccdlane::cli
