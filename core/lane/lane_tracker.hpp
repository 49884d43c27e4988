// Lane-line identities across frames: a line keeps its id while detection continues it
// from the previous frame's lines; a line missed for a few frames coasts (moved sideways
// with the others) and keeps its id when it is found again; new lines get fresh ids.
// Ids follow the road, so through a lane change the line passing under the vehicle keeps
// its id.
#pragma once

#include <array>
#include <span>

#include "core/detection/lane_marks.hpp"

namespace ccdlane {

class LaneTracker {
 public:
  static constexpr int kCoastFrames = 15;  // how long a missed line is still looked for
  static constexpr int kCapacity = 8;      // lines in view plus coasting ones

  // The lines detection should look for first this frame (road frame): last frame's,
  // then the coasting ones.
  std::span<const RoadLine> priors() const { return {lines_.data(), static_cast<std::size_t>(count_)}; }

  // After a frame's lines are known: `lines` (road frame) and, per line, the index into
  // priors() it continues (-1 = new). Writes each line's id. When nothing continues and
  // nothing coasts (the first frame, after a loss), ids restart at 0, left to right.
  void update(std::span<const RoadLine> lines, std::span<const int> prior_index, std::span<int> ids);

  // A frame without lines: everything coasts one frame.
  void coast();

  // The lines seen from `factor` times the height they were measured at (the picture of
  // a flat road fixes every distance only in proportion to the height): offsets scale
  // by it, curvatures by its inverse, slopes stay.
  void rescale(double factor);

  // Forgets everything.
  void reset() { count_ = 0; }

 private:
  std::array<RoadLine, kCapacity> lines_{};
  std::array<int, kCapacity> ids_{};
  std::array<int, kCapacity> missed_{};  // frames since each was last seen
  int count_ = 0;
  int next_id_ = 0;
};

}  // namespace ccdlane
