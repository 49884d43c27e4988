// Raised pavement markers in sunlight, along one image row. A Botts' dot is a white dome
// about 10 cm across: the sun lights one side of it and the other side, with the patch of
// road behind it, lies in its shadow. Seen from 10-30 m its lit cap is 2-4 pixels wide,
// narrower than the row filter's bars can be (mark_scanner.hpp) and narrower than noise
// often is; what gives it away is the pair: a bright cap against a dark shadow, each
// standing out from the road on its own, both together no wider than a marker and its
// shadow, on a road that is smooth beside them. The detector then checks that the pair is
// as short as a marker on the road (lane_detector.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "core/detection/lane_marks.hpp"
#include "core/detection/scan_row.hpp"

namespace ccdlane {

class DotScanner {
 public:
  explicit DotScanner(int max_width);

  // Appends the cap-and-shadow pairs on row r.y (r.dot_px > 0) of `row` (the row's paint
  // measure over r's columns [x_begin, x_end): row[0] is column x_begin; `prefix` its
  // prefix sums, prefix[0] = 0) to out[count..capacity); returns the new count. A pair
  // whose cap lies on a bar out[first_of_row..count) already holds is not appended again.
  // Sets left/right_px symmetric about the edge between cap and shadow (the dome's
  // middle) as wide as two caps (the dome), py, contrast (the weaker of the two, 8-bit
  // scale), scan_row, shadow_side and shadow_px, and `narrow` (it is a candidate only as
  // a dot).
  template <typename Pixel>
  int scan(const Pixel* row, const std::int32_t* prefix, int x_begin, int width, const ScanRow& r, int scan_row,
           float min_contrast, float to_8bit, MarkCandidate* out, int first_of_row, int count, int capacity);

 private:
  struct Run {
    std::int32_t begin, end;  // pixels [begin, end) of the segment
    std::int8_t sign;         // +1 brighter than the road around it, -1 darker
  };
  std::vector<std::int8_t> class_;  // per pixel: +1 brighter, -1 darker than the road, 0
  std::vector<Run> runs_;
};

}  // namespace ccdlane
