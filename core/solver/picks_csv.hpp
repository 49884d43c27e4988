// The picks CSV of docs/interfaces.md ("line,px,py"), parsed from text with errors that name
// the file, the line and the field. For tools and start-up, not the real-time path.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/solver/lane_solver.hpp"

namespace ccdlane {

// One line: "<source>:<line>: <field>: <what>" (or "<source>: <what>").
class PicksCsvError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PicksCsv {
  std::vector<Pick> picks;
  std::vector<int> source_lines;  // 1-based line of each pick in the text, for messages
};

// Header `line,px,py` (fields may be padded with blanks), then one pick per row; blank
// lines and lines starting with '#' are ignored. Throws PicksCsvError on the first
// problem, or when there are no picks at all.
PicksCsv parse_picks_csv(std::string_view text, const std::string& source_name);

}  // namespace ccdlane
