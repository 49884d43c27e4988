// Overlay drawing (plain DDA lines and crosses on an RGB buffer) and PNG output through the
// frame driver's codec.
#include "tools/ccdlane/overlay_png.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "core/detection/paint_measure.hpp"
#include "drivers/frames/png.hpp"
#include "tools/ccdlane/road_line_picture.hpp"

namespace ccdlane::cli {
namespace {

// Distinct colours for lines 0, 1, 2, ... (left to right).
constexpr std::array<std::uint8_t, 3> kLineColours[] = {
    {255, 60, 60},  {60, 220, 60}, {70, 140, 255}, {255, 200, 0},
    {230, 80, 255}, {0, 230, 230}, {255, 140, 0},  {160, 255, 160},
};
constexpr std::array<std::uint8_t, 3> kUngrouped = {150, 150, 150};

const std::array<std::uint8_t, 3>& colour(int line) {
  return kLineColours[static_cast<std::size_t>(line) % (sizeof kLineColours / sizeof kLineColours[0])];
}

}  // namespace

Overlay::Overlay(const ImageView& frame)
    : width_(frame.width), height_(frame.height), rgb_(static_cast<std::size_t>(frame.width) * frame.height * 3) {
  if (is_colour(frame.format)) {
    const bool bgr = frame.format == PixelFormat::bgr8;
    for (int y = 0; y < height_; ++y) {
      const std::uint8_t* in = frame.row(y);
      std::uint8_t* out = &rgb_[static_cast<std::size_t>(y) * width_ * 3];
      for (int x = 0; x < width_; ++x, in += 3, out += 3) {
        out[0] = in[bgr ? 2 : 0];
        out[1] = in[1];
        out[2] = in[bgr ? 0 : 2];
      }
    }
    return;
  }
  const int shift = frame.format == PixelFormat::mono16 ? std::max(0, frame.significant_bits - 8) : 0;
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const auto v = static_cast<std::uint8_t>(std::min(255, frame.at(x, y) >> shift));
      std::uint8_t* p = &rgb_[(static_cast<std::size_t>(y) * width_ + x) * 3];
      p[0] = p[1] = p[2] = v;
    }
}

std::array<std::uint8_t, 3> Overlay::pixel(int x, int y) const {
  const std::uint8_t* p = &rgb_[(static_cast<std::size_t>(y) * width_ + x) * 3];
  return {p[0], p[1], p[2]};
}

void Overlay::put(int x, int y, const std::array<std::uint8_t, 3>& rgb) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  std::memcpy(&rgb_[(static_cast<std::size_t>(y) * width_ + x) * 3], rgb.data(), 3);
}

void Overlay::line(double x0, double y0, double x1, double y1, const std::array<std::uint8_t, 3>& rgb) {
  const double len = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  const int steps = std::max(1, static_cast<int>(std::ceil(len)));
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    put(static_cast<int>(std::lround(x0 + t * (x1 - x0))), static_cast<int>(std::lround(y0 + t * (y1 - y0))), rgb);
  }
}

void Overlay::draw_vanishing_point(const VanishingPoint& vp) {
  // The region searched as a dim frame; the point (when found) as a cross with the
  // horizon through it.
  constexpr std::array<std::uint8_t, 3> kRegion{0, 110, 110}, kPoint{255, 0, 255};
  line(vp.x_lo - 1.0, vp.y_lo - 1.0, vp.x_hi - 1.0, vp.y_lo - 1.0, kRegion);
  line(vp.x_lo - 1.0, vp.y_hi - 1.0, vp.x_hi - 1.0, vp.y_hi - 1.0, kRegion);
  line(vp.x_lo - 1.0, vp.y_lo - 1.0, vp.x_lo - 1.0, vp.y_hi - 1.0, kRegion);
  line(vp.x_hi - 1.0, vp.y_lo - 1.0, vp.x_hi - 1.0, vp.y_hi - 1.0, kRegion);
  if (!vp.found) return;
  line(0.0, vp.y - 1.0, width_ - 1.0, vp.y - 1.0, kRegion);
  line(vp.x - 13.0, vp.y - 1.0, vp.x + 11.0, vp.y - 1.0, kPoint);
  line(vp.x - 1.0, vp.y - 13.0, vp.x - 1.0, vp.y + 11.0, kPoint);
}

void Overlay::draw_marks(std::span<const MarkCandidate> marks) {
  for (const MarkCandidate& m : marks) {
    // 1-based pixel centres to 0-based buffer positions.
    const auto& c = m.line >= 0 ? colour(m.line) : kUngrouped;
    line(m.left_px - 1, m.py - 1, m.right_px - 1, m.py - 1, c);
  }
}

void Overlay::draw_picks(std::span<const Pick> picks) {
  for (const Pick& p : picks) {
    const double x = p.px - 1, y = p.py - 1;
    line(x - 3, y - 3, x + 3, y + 3, colour(p.line));
    line(x - 3, y + 3, x + 3, y - 3, colour(p.line));
  }
}

void Overlay::draw_road_line(const CameraModel& camera, const RoadLine& road, double near_mm, double far_mm,
                             int line_index) {
  std::optional<Vec2> previous;
  for (const std::optional<Vec2>& p : road_line_pixels(camera, road, near_mm, far_mm, 60)) {
    if (p && previous) line(previous->x() - 1, previous->y() - 1, p->x() - 1, p->y() - 1, colour(line_index));
    previous = p;
  }
}

void Overlay::draw_road_line_by_rows(const CameraModel& camera, const RoadLine& road, double near_mm, double far_mm,
                                     int line_index) {
  std::optional<double> previous;
  for (int row = 1; row <= height_; ++row) {
    const std::optional<double> x = road_line_column_at_row(camera, road, row, near_mm, far_mm);
    if (x && previous) line(*previous - 1, row - 2, *x - 1, row - 1, colour(line_index));
    previous = x;
  }
}

void Overlay::draw_lane_point(const Vec2& point, bool hit, bool ego) {
  const double r = ego ? 4.0 : 3.0;
  const auto& c = hit ? kHitPoint : kMissedPoint;
  constexpr int kSteps = 24;
  for (int i = 0; i < kSteps; ++i) {
    const double a0 = 2.0 * kPi * i / kSteps, a1 = 2.0 * kPi * (i + 1) / kSteps;
    line(point.x() - 1 + r * std::cos(a0), point.y() - 1 + r * std::sin(a0), point.x() - 1 + r * std::cos(a1),
         point.y() - 1 + r * std::sin(a1), c);
  }
}

void Overlay::write_png(const std::string& path) const { ccdlane::write_png(path, view(), 3); }

void write_paint_measure_png(const std::string& path, const ImageView& frame, int first_row, int last_row) {
  std::vector<std::uint8_t> grey(static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height));
  const MutableImageView out{grey.data(), frame.width, frame.height, frame.width, PixelFormat::mono8, 8};
  render_paint_measure(frame, out);
  for (int y = 0; y < frame.height; ++y)
    if (y < first_row || y > last_row)
      for (int x = 0; x < frame.width; ++x) out.row(y)[x] = static_cast<std::uint8_t>(out.row(y)[x] / 4);
  ccdlane::write_png(path, out, 3);
}

}  // namespace ccdlane::cli
