// What the row filters (mark_scanner.hpp, dot_scanner.hpp) are told of one row.
#pragma once

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
  // A raised marker's width along this row, pixels, where the row is also searched for
  // markers lit from one side (a cap beside its shadow, dot_scanner.hpp); 0: not.
  float dot_px = 0.0f;
  // The widest joint between concrete slabs along this row, pixels, where the row is also
  // searched for joints (dark lines beside raised markers, MarkScanner); 0: not.
  float max_joint_px = 0.0f;
  // The narrowest black border of contrast markings along this row, pixels (less one of
  // blur): a bar between two such bands is paint with its borders, not beside a step
  // (MarkScanner). By default no band is.
  float min_border_px = 1e30f;
  int half_width = 1;  // of the box derivative (noise averaging at the mark's scale)
  // The columns scanned, 0-based [x_begin, x_end) (clipped to the picture): where the
  // road searched lies on this row. Pixels outside are never read, nor is their paint
  // measure computed.
  int x_begin = 0;
  int x_end = 1 << 30;
};

}  // namespace ccdlane
