// Raised markers in the gap between a line's nearest mark and the car
// (lane_estimator.cpp): where a dashed line's nearest dash is metres ahead, the line is
// drawn on to the car from its farther paint, and how far off it runs there grows with
// the rows it is drawn over (docs/real-roads.md, "where the own lines leave their labels
// near the car"). A raised marker set in that gap says where the line runs.
#pragma once

#include <span>

#include "core/detection/lane_marks.hpp"
#include "core/geometry/camera_model.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane {

// How far from a line's extension a marker in its gap may lie, across the road in pixels
// at the marker's distance: the extension's own spread 120-240 rows below its nearest
// pick (75th percentile 16-19 px on the TuSimple stills). 15 px took too few of them,
// 40 px as many as 25.
constexpr double kGapMarkerWindowPx = 25.0;

// The marks of `marks` that are raised markers (a lit cap found beside its own shadow,
// MarkCandidate::shadow_side) in no line, lying in the picture below the nearest of the
// picks of solved line `line` (index `line_index` among `picks`) and within
// kGapMarkerWindowPx of the line's extension, seen by `camera` (the solve's pose): as
// picks of that line, written to `out` while it has room. Returns how many.
// Plain dots are not taken: on asphalt the gaps hold specks a dot test passes, and
// taken so they doubled a drive's frame-to-frame offset steps when each picture was
// searched alone.
int gap_markers(std::span<const MarkCandidate> marks, std::span<const Pick> picks, const CameraModel& camera,
                const RoadLine& line, int line_index, std::span<Pick> out);

}  // namespace ccdlane
