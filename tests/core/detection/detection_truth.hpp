// Detection against a rendered frame's truth: which truth line each detected line is, and
// how far each pick lies from the truth line its label claims.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/detection/lane_detector.hpp"
#include "core/geometry/camera_model.hpp"
#include "tests/core/synth/truth_projection.hpp"

namespace ccdlane::test {

// Pick errors against the truth line each pick's label claims: the distance from the
// line in pixels (the error along the row times the cosine of the line's slant; what the
// solver's residual sees).
struct PickErrors {
  double rms = 0, worst = 0;
  int n = 0;
};
inline PickErrors pick_errors(const DetectionResult& r, const SynthFrame& f, const CameraModel& cam,
                              const std::vector<int>& truth_line_of) {
  PickErrors e;
  double sum2 = 0;
  for (const Pick& p : r.picks) {
    const int t = truth_line_of[static_cast<std::size_t>(p.line)];
    const auto want = test::truth_column(cam, f, t, p.py);
    const auto above = test::truth_column(cam, f, t, p.py - 1), below = test::truth_column(cam, f, t, p.py + 1);
    if (!want || !above || !below) continue;
    const double slope = 0.5 * (*below - *above);  // columns per row
    const double d = (p.px - *want) / std::sqrt(1.0 + slope * slope);
    sum2 += d * d;
    e.worst = std::max(e.worst, std::abs(d));
    ++e.n;
  }
  e.rms = e.n ? std::sqrt(sum2 / e.n) : 0.0;
  return e;
}

// Which truth line each detected line is (nearest y0 at the true pose).
inline std::vector<int> match(const DetectionResult& r, const SynthFrame& f) {
  std::vector<int> m;
  for (int j = 0; j < r.num_lines; ++j) {
    int best = 0;
    for (int t = 1; t < f.num_lines; ++t)
      if (std::abs(f.y0_mm[t] - r.lines[j].fit.y0_mm) < std::abs(f.y0_mm[best] - r.lines[j].fit.y0_mm)) best = t;
    m.push_back(best);
  }
  return m;
}

}  // namespace ccdlane::test
