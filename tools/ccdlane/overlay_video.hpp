// The annotated video of `ccdlane replay --overlay-video`: every frame with the lines
// found, the own lane filled, the candidate marks faint, a strip of the lane's figures,
// and a departure warning on its side while it is held; H.264 at the input's frame times.
#pragma once

#include <cstdint>
#include <string>

#include "app/config.hpp"
#include "core/lane/lane_estimator.hpp"
#include "drivers/frames/video_writer.hpp"

namespace ccdlane::cli {

// The strip's text: "width 3.66 m | offset +0.12 m | heading -1.3 deg | radius straight |
// ok, tracking | LDW available" (figures "-" on a frame not ok).
std::string overlay_strip_text(const LaneEstimate& e);

class OverlayVideo {
 public:
  // Creates `path` (whole or absent, VideoWriter); times in the given time base (the
  // input video's, so that they stay exactly the input's). Throws std::runtime_error.
  OverlayVideo(const std::string& path, int width, int height, int time_base_num, int time_base_den);

  // Draws `e` (what `estimator` found on `frame`) over the frame and appends it at e.t_ns.
  void add(const ImageView& frame, const LaneEstimate& e, const LaneEstimator& estimator, const Config& config);
  void finish() { writer_.finish(); }
  std::uint64_t frames() const { return writer_.frames(); }

 private:
  VideoWriter writer_;
};

}  // namespace ccdlane::cli
