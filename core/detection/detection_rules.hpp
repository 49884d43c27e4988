// What lane detection's parts share (lane_detector.cpp, lane_detector_marks.cpp,
// lane_detector_picture.cpp): the sizes of raised markers and joints on the road and in the
// picture's rows.
#pragma once

#include <cmath>

#include "core/detection/lane_marks.hpp"

namespace ccdlane::detection_rules {

// A Botts' dot or raised marker is about 10 cm long on the road; blur and a pose error
// make it look longer. Anything that stands above its surroundings over less of the road
// than this (plus a pixel or two of blur) is a blob, not a piece of a line.
inline constexpr double kMaxDotLengthMm = 300.0;
inline constexpr double kDotBlurPx = 2.0;
// Lit from one side, a marker is a cap beside its shadow (dot_scanner.hpp), looked for
// where the dome (10 cm) spans this many pixels: fewer, and cap and shadow blur into one.
inline constexpr double kDotDiameterMm = 100.0;
// Joints between concrete slabs are sealed cuts a centimetre or two wide; with blur and
// a worn edge, this wide at most.
inline constexpr double kMaxJointWidthMm = 40.0;

// The widest a joint between slabs (or a sealed crack's bead) looks where one pixel spans
// `mm_per_px` of the road across it.
inline double max_joint_px(double mm_per_px) { return kMaxJointWidthMm / mm_per_px + kDotBlurPx; }

// How many rows a marker may span where one row spans `mm_per_px_down` of the road (at
// least 1 mm); 0 where a row spans more of the road than a marker is long: farther, a
// dash is a few rows tall too, and blobs are not told from paint.
inline int dot_rows_for(double mm_per_px_down) {
  if (mm_per_px_down > kMaxDotLengthMm) return 0;
  return static_cast<int>(std::ceil(kMaxDotLengthMm / mm_per_px_down + kDotBlurPx));
}

}  // namespace ccdlane::detection_rules
