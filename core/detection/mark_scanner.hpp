// The row filter: finds dark-bright-dark bars of the lane-paint measure along one image
// row whose width is what a lane mark at that row's distance would have, with sub-pixel
// edges.
#pragma once

#include <cstdint>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/lane_marks.hpp"

namespace ccdlane {

// How to scan one row: derived per frame from the camera model and the current pose.
struct ScanRow {
  int y = 0;               // 0-based image row
  float mark_px = 1.0f;    // expected mark width along this row, pixels
  float min_width_px = 1;  // accepted bar widths
  float max_width_px = 4;
  // Narrower bars, down to this, are kept flagged `narrow`: the lit cap of a raised
  // marker is narrower than paint, and only a short blob may be that narrow (the
  // detector's test). By default none.
  float min_dot_width_px = 1e30f;
  int half_width = 1;  // of the box derivative (noise averaging at the mark's scale)
  // The columns scanned, 0-based [x_begin, x_end) (clipped to the picture): where the
  // road searched lies on this row. Pixels outside are never read, nor is their paint
  // measure computed.
  int x_begin = 0;
  int x_end = 1 << 30;
};

class MarkScanner {
 public:
  // Buffers for rows up to `max_width` pixels are allocated here, none in scan().
  explicit MarkScanner(int max_width);

  // Appends the bars found on row r.y of `image` to out[count..capacity), returns the new
  // count. `min_contrast` is in the paint measure's levels (paint_measure.hpp: a grey
  // frame's own grey levels). Sets left/right_px, py,
  // contrast (8-bit scale via `to_8bit`) and scan_row; the rest is the caller's.
  int scan(const ImageView& image, const ScanRow& r, int scan_row, float min_contrast, float to_8bit,
           MarkCandidate* out, int count, int capacity);

 private:
  struct Edge {
    float x;  // 0-based position of the edge (between pixels: x + 0.5 of the left one)
    std::int32_t strength;
  };
  template <typename Pixel>
  int scan_row(const Pixel* row, int x_begin, int x_end, const ScanRow& r, int scan_row, float min_contrast,
               float to_8bit, MarkCandidate* out, int count, int capacity);

  std::vector<std::uint16_t> measure_;  // a colour row's paint measure
  std::vector<std::int32_t> prefix_;    // prefix sums of the row (65535 x 2^15 pixels fit)
  std::vector<std::int32_t> grad_;      // box derivative
  std::vector<Edge> rising_, falling_;
};

}  // namespace ccdlane
