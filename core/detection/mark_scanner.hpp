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

  // The picture's blur, from the edges of the clear bars scanned since clear_edges(): a
  // blurred step's steepest one-pixel rise is its contrast / (sigma sqrt(2 pi)). How many
  // pixels farther from a bar's edges the step test reads (0-2, MarkCandidate::
  // step_beside_at): none on pictures as sharp as those it was set on, one more for each
  // 2/3 pixel of blur beyond them, where a blurred edge's ramp still falls.
  void clear_edges() { num_edge_ramps_ = 0; }
  int step_window_offset();

  // The sharpest edges' sigma the step test was set on (the development set's pictures:
  // median edge ratios 2.9-3.0, their stills up to 3.7 at the 90th percentile), and the
  // ramp beyond an edge per pixel of sigma (a Gaussian-blurred step is within 7 % of its
  // level 1.5 sigma from the edge).
  static constexpr double kSharpEdgeSigmaPx = 1.36;
  static constexpr double kRampPerSigma = 1.5;
  static constexpr int kMaxStepWindowOffset = 2;
  // Edges measured: of bars at least this wide, standing twice the threshold above both
  // sides; at least this many for a measure.
  static constexpr float kMinRampBarPx = 5.0f;
  static constexpr int kMinRampEdges = 8;

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

  // Records a clear bar's two edges' ratios of contrast to steepest rise (edge_ramps_).
  template <typename Pixel>
  void add_edge_ramps(const Pixel* row, int width, int ia, int ib, float left_contrast, float right_contrast);
  static constexpr int kMaxEdgeRamps = 4096;

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
  // Per clear bar's edge: its contrast over its steepest one-pixel rise (sigma sqrt(2 pi)).
  std::vector<float> edge_ramps_;
  int num_edge_ramps_ = 0;
  DotScanner dots_;
};

}  // namespace ccdlane
