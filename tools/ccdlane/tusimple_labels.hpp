// TuSimple's lane labels (and CULane's per-picture .lines.txt) read into the annotated
// lanes `ccdlane score` compares replay's lines with.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "tools/ccdlane/lane_score.hpp"

namespace ccdlane::cli {

// One labelled picture: the path the label gives and its lanes (1-based pixels), each
// with TuSimple's angle-scaled threshold and the ego lanes marked.
struct LabelledPicture {
  std::vector<std::string> images;  // "image" and "raw_file", whichever the label gives
  std::vector<AnnotatedLane> lanes;
  std::vector<double> rows;  // "h_samples", 1-based: the rows TuSimple's own benchmark samples
};

// TuSimple's label file: one JSON object per line with "h_samples" (0-based rows),
// "lanes" (per lane one 0-based x per row, negative where the lane has no point) and the
// picture's path in "raw_file" (TuSimple's own, in its clips/ tree) or "image" (a copy's). Pictures are width x height.
// Throws UsageError naming the file and line of the first malformed label.
std::vector<LabelledPicture> read_tusimple_labels(const std::string& path, int width, int height);

// CULane's label of one picture: one lane per line, "x y x y ..." (0-based pixels).
// Throws UsageError naming the file and line.
std::vector<AnnotatedLane> read_culane_lines(const std::string& path, int width, int height);

// Whether a frame file (as frames.csv names it) is the labelled picture `image`: one
// path ends with the other at a path separator (labels give paths relative to their
// dataset's root, frames.csv absolute or relative to the frame directory).
bool same_picture(std::string_view frame_file, std::string_view image);

}  // namespace ccdlane::cli
