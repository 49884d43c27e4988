// Test videos: see test_video.hpp.
#include "tests/support/test_video.hpp"

#include <algorithm>
#include <cstdlib>

namespace ccdlane::test {

void paint_test_frame(const MutableImageView& into, int index) {
  for (int y = 0; y < into.height; ++y)
    for (int x = 0; x < into.width; ++x) {
      std::uint8_t* p = into.row(y) + bytes_per_pixel(into.format) * x;
      const int v = (2 * x + 3 * y + 7 * index) % 200 + 20;
      for (int c = 0; c < bytes_per_pixel(into.format); ++c) p[c] = static_cast<std::uint8_t>(v + 10 * c);
    }
}

std::string write_test_video(const std::string& path, int width, int height, const std::vector<std::int64_t>& times_ns,
                             VideoWriterOptions options) {
  options.width = width;
  options.height = height;
  VideoWriter writer(path, options);
  const ImageBuffer frame(width, height, PixelFormat::rgb8, 8);
  for (std::size_t i = 0; i < times_ns.size(); ++i) {
    paint_test_frame(frame.view(), static_cast<int>(i));
    writer.write(frame.view(), times_ns[i]);
  }
  writer.finish();
  return path;
}

int max_abs_difference(const ImageView& a, const ImageView& b) {
  int worst = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width * bytes_per_pixel(a.format); ++x)
      worst = std::max(worst, std::abs(int{a.row(y)[x]} - int{b.row(y)[x]}));
  return worst;
}

double mean_abs_difference(const ImageView& a, const ImageView& b) {
  double sum = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width * bytes_per_pixel(a.format); ++x) sum += std::abs(int{a.row(y)[x]} - int{b.row(y)[x]});
  return sum / (static_cast<double>(a.height) * a.width * bytes_per_pixel(a.format));
}

}  // namespace ccdlane::test
