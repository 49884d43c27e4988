// One line of `ccdlane replay`'s output as `ccdlane score` reads it back: the frame and,
// when it was solved, the attitude and the lines. Every field is checked for its type
// and finiteness, so that a damaged line is one message naming the field, never a JSON
// library's error or a crash (a `lines` entry of {} once was a SIGSEGV).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/detection/lane_marks.hpp"

namespace ccdlane::cli {

struct ReplayAttitude {
  double psi_deg = 0.0, theta_deg = 0.0, phi_deg = 0.0;
  std::optional<double> H_mm;  // the height the lines are at; empty: the configuration's
};

struct ReplayLine {
  std::uint64_t frame = 0;
  std::optional<ReplayAttitude> attitude;  // empty: not solved (no psi_deg)
  std::vector<RoadLine> lines;            // read only with an attitude
  // Per line, where its nearest mark is on the road (`near_mm`, its view range's near
  // end); empty where the line does not say (replays before view ranges were written).
  std::vector<std::optional<double>> near_mm;
};

// "" and `out`, or the problem naming the field: "not a JSON object", "frame: not a frame
// number", "theta_deg: not a number", "lines[1].m: not a number", "lines: not an array",
// "lines[0].near_mm: not a distance" (present, but not a number above 0).
std::string parse_replay_line(std::string_view text, ReplayLine& out);

}  // namespace ccdlane::cli
