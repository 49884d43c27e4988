// Frames drawn on the road with exactly known markers: raised markers (plain, or lit by a
// low sun beside their shadow), the sealed joint between concrete slabs, stripes of paint and a concrete
// texture; the fixture of the detector's tests of what concrete roads are marked with.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "app/config.hpp"
#include "app/config_loader.hpp"
#include "base/image_view.hpp"
#include "core/detection/ground_projector.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane::test {

struct Frame {
  std::vector<std::uint8_t> px;
  MutableImageView view;
  explicit Frame(const CameraSpec& cam, PixelFormat f = PixelFormat::mono8, int bits = 8)
      : px(static_cast<std::size_t>(cam.Nu * cam.Nv * bytes_per_pixel(f))) {
    view = {px.data(), cam.Nu, cam.Nv, cam.Nu * bytes_per_pixel(f), f, bits};
  }
};

// Paints a marker centred at (X, Y) on the road: `grey(dx, dy)` is its grey level at an
// offset on the road from its centre, mm (-1: the road's own), averaged over each pixel.
template <typename Grey>
void draw_marker(const MutableImageView& im, const GroundProjector& ground, const CameraModel& model, double X,
                 double Y, const Grey& grey) {
  const auto centre = model.pixel_from_point(Vec3(X, Y, 0.0));
  if (!centre) return;
  const int cx = static_cast<int>(centre->x()) - 1, cy = static_cast<int>(centre->y()) - 1;
  constexpr int kSamples = 4;  // per pixel side: a far dot covers part of a pixel, as a lens blurs it
  for (int y = std::max(0, cy - 20); y <= std::min(im.height - 1, cy + 20); ++y)
    for (int x = std::max(0, cx - 40); x <= std::min(im.width - 1, cx + 40); ++x) {
      std::uint8_t& p = im.row(y)[x];
      int sum = 0;
      for (int sy = 0; sy < kSamples; ++sy)
        for (int sx = 0; sx < kSamples; ++sx) {
          double gx = 0, gy = 0;
          const int g = ground.ground(x + 0.5 + (sx + 0.5) / kSamples, y + 0.5 + (sy + 0.5) / kSamples, gx, gy)
                            ? grey(gx - X, gy - Y)
                            : -1;
          sum += g < 0 ? p : g;
        }
      p = static_cast<std::uint8_t>(sum / (kSamples * kSamples));
    }
}

constexpr double kDotRadiusMm = 50.0;

inline void draw_dot(const MutableImageView& im, const GroundProjector& ground, const CameraModel& model, double X,
                     double Y, std::uint8_t grey) {
  draw_marker(im, ground, model, X, Y,
              [grey](double dx, double dy) { return std::hypot(dx, dy) <= kDotRadiusMm ? int{grey} : -1; });
}

// The same marker in sunlight from the left, raised as Botts' dots are (18 mm): its dome
// hides the road for h X / H beyond it, so it looks that much longer than its footprint.
// Lit only on its outer 30 mm on the sun's side (narrower than a bar the detector takes
// alone); the rest of the dome, and its shadow on the road as long, dark.
inline void draw_sunlit_dot(const MutableImageView& im, const GroundProjector& ground, const CameraModel& model,
                            double X, double Y, double height_mm) {
  constexpr double kDomeMm = 18.0;
  const double length = kDotRadiusMm + 0.5 * kDomeMm * X / height_mm;  // half, along the road
  draw_marker(im, ground, model, X, Y, [length](double dx, double dy) {
    const double along = dx / length;
    if (std::hypot(along, dy / kDotRadiusMm) <= 1.0) return dy > kDotRadiusMm - 30.0 ? 230 : 70;
    return std::hypot(along, (dy + 40.0) / kDotRadiusMm) <= 1.0 ? 70 : -1;
  });
}

inline void concrete(const MutableImageView& im, std::uint32_t seed) {
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      seed = seed * 1664525u + 1013904223u;
      im.row(y)[x] = static_cast<std::uint8_t>(150 + static_cast<int>((seed >> 24) % 9) - 4);
    }
}

// A band along the road at Y, from X_near to X_far, `width_mm` wide and `grey`: the sealed
// joint between two concrete slabs (dark), or a stripe of paint (bright). Each pixel takes
// the band's grey by the share of it the band covers on the road (a far joint is a
// fraction of a pixel, as a lens blurs it).
inline void draw_band(const MutableImageView& im, const GroundProjector& ground, const CameraModel& model, double Y,
                      double X_near, double X_far, double width_mm, std::uint8_t grey) {
  constexpr int kSamples = 4;  // per pixel side
  for (int y = 0; y < im.height; ++y) {
    double X = 0.0, Yc = 0.0;
    if (!ground.ground(model.spec().cx, y + 1.0, X, Yc) || X < 0.9 * X_near || X > 1.1 * X_far) continue;
    const auto at = model.pixel_from_point(Vec3(X, Y, 0.0));
    if (!at) continue;
    const int cx = static_cast<int>(at->x()) - 1;
    for (int x = std::max(0, cx - 30); x <= std::min(im.width - 1, cx + 30); ++x) {
      int covered = 0;
      for (int sy = 0; sy < kSamples; ++sy)
        for (int sx = 0; sx < kSamples; ++sx) {
          double gx = 0, gy = 0;
          covered += ground.ground(x + 0.5 + (sx + 0.5) / kSamples, y + 0.5 + (sy + 0.5) / kSamples, gx, gy) &&
                     gx >= X_near && gx <= X_far && std::abs(gy - Y) <= 0.5 * width_mm;
        }
      std::uint8_t& p = im.row(y)[x];
      p = static_cast<std::uint8_t>(std::lround(p + covered * (grey - p) / double{kSamples * kSamples}));
    }
  }
}

// Seen by TuSimple's camera from where the solver puts it for its stills: 1.69 m up,
// 7.3 degrees down (a dot 10 m off spans two rows).
inline CameraPose tusimple_pose(const Config& c) {
  CameraPose pose = c.nominal_pose();
  pose.attitude.theta = deg_to_rad(7.3);
  pose.H_mm = 1690.0;
  return pose;
}

// A concrete road (texture of `seed`) in front of TuSimple's camera at tusimple_pose, to
// draw markers and stripes on.
struct TuSimpleConcreteRoad {
  Config c = load_config_file(std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple/camera.toml");
  CameraPose pose = tusimple_pose(c);
  GroundProjector ground{c.camera, pose};
  CameraModel model{c.camera, pose};
  Frame frame{c.camera};

  explicit TuSimpleConcreteRoad(std::uint32_t seed) { concrete(frame.view, seed); }
};

}  // namespace ccdlane::test
