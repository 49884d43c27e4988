// The row filter: finds dark-bright-dark bars of the lane-paint measure along one image
// row whose width is what a lane mark at that row's distance would have, with sub-pixel
// edges.
#pragma once

#include <cstdint>
#include <vector>

#include "base/image_view.hpp"
#include "core/detection/dot_scanner.hpp"
#include "core/detection/lane_marks.hpp"
#include "core/detection/scan_row.hpp"

namespace ccdlane {

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
    // A falling edge's rising one before it, with no falling one between (a bar's two
    // edges); a rising edge's falling one so (a joint's); -1: none.
    std::int32_t partner;
  };
  template <typename Pixel>
  int scan_row(const Pixel* row, int x_begin, int x_end, const ScanRow& r, int scan_row, float min_contrast,
               float to_8bit, MarkCandidate* out, int count, int capacity);

  // Joints along a row: each rising edge paired with its partner, the last falling one
  // before it.
  template <typename Pixel>
  int scan_joints(const Pixel* row, int x_begin, int width, const ScanRow& r, int scan_row, float min_contrast,
                  float to_8bit, int n_rising, MarkCandidate* out, int first_of_row, int count, int capacity) const;

  std::vector<std::uint16_t> measure_;  // a colour row's paint measure
  std::vector<std::int32_t> prefix_;    // prefix sums of the row (65535 x 2^15 pixels fit)
  std::vector<std::int32_t> grad_;      // box derivative
  std::vector<std::uint8_t> extrema_;   // per boundary: 1 a rising edge's peak, 2 a falling one's
  std::vector<Edge> rising_, falling_;
  DotScanner dots_;
};

}  // namespace ccdlane
