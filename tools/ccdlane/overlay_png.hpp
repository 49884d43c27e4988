// Overlay pictures for looking at what detection and the solver did on a frame: the frame
// (in colour when it is), every candidate mark, the picks coloured by line, and the fitted
// lines; and the lane-paint measure detection scanned, as a picture of its own.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/lane_marks.hpp"
#include "core/detection/vanishing_point.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane::cli {

// An RGB picture being drawn on.
class Overlay {
 public:
  // The frame as background: colour frames as they are, grey ones grey (16-bit scaled down).
  explicit Overlay(const ImageView& frame);

  // Candidate marks: small ticks, grey for ungrouped ones, the line's colour otherwise.
  void draw_marks(std::span<const MarkCandidate> marks);
  // Picks: crosses in their line's colour.
  void draw_picks(std::span<const Pick> picks);
  // A road line y = y0 + m x + c x^2 from near_mm to far_mm, projected through `camera`.
  void draw_road_line(const CameraModel& camera, const RoadLine& line, double near_mm, double far_mm, int colour);
  // The same line as `ccdlane score` samples it: its column on each picture row it
  // crosses between near_mm and far_mm ahead.
  void draw_road_line_by_rows(const CameraModel& camera, const RoadLine& line, double near_mm, double far_mm,
                              int colour);
  // An annotated lane point (1-based pixel): a ring, green where a reported line hits it,
  // red where none does; larger for the own lane's lines.
  void draw_lane_point(const Vec2& point, bool hit, bool ego);
  static constexpr std::array<std::uint8_t, 3> kHitPoint{0, 255, 0}, kMissedPoint{255, 0, 0};

  // The region the vanishing point was searched in, and the point with the horizon
  // through it when one was found (ideal pixels, drawn as they are: near the picture's
  // centre distortion moves them by less than a pixel).
  void draw_vanishing_point(const VanishingPoint& vp);

  // Writes a PNG (drivers/frames/png.hpp). Throws std::runtime_error naming the file on failure; the file
  // is written under a temporary name and renamed, so it is whole or absent.
  void write_png(const std::string& path) const;

  int width() const { return width_; }
  ImageView view() const {
    return {rgb_.data(), width_, height_, static_cast<std::ptrdiff_t>(width_) * 3, PixelFormat::rgb8, 8};
  }
  int height() const { return height_; }
  std::array<std::uint8_t, 3> pixel(int x, int y) const;

 private:
  void put(int x, int y, const std::array<std::uint8_t, 3>& rgb);
  void line(double x0, double y0, double x1, double y1, const std::array<std::uint8_t, 3>& rgb);

  int width_, height_;
  std::vector<std::uint8_t> rgb_;
};

// The lane-paint measure of `frame` (core/detection/paint_measure.hpp) as an 8-bit grey
// PNG: bright where detection sees paint. Rows outside [first_row, last_row] (0-based, the
// band detection searched) are drawn at a quarter of their brightness. Whole or absent,
// as Overlay::write_png.
void write_paint_measure_png(const std::string& path, const ImageView& frame, int first_row, int last_row);

}  // namespace ccdlane::cli
