// The index of a frame directory (docs/interfaces.md "Frame directories"): frames.csv with
// required file,t_ns, optional gyro roll_deg,pitch_deg,yaw_deg, optional vehicle
// speed_kmh,turn_indicator, and any truth_* columns, in any column order.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/gx1_angles.hpp"
#include "base/turn_indicator.hpp"
#include "drivers/frames/frame_directory_error.hpp"

namespace ccdlane {

struct FrameRow {
  std::size_t index = 0;  // 0-based data row of frames.csv: the frame number
  int line = 0;           // 1-based line of frames.csv, for messages
  std::string file;       // as written in frames.csv
  std::int64_t t_ns = 0;
  std::optional<Gx1Angles> gyro;                  // when the row has roll_deg and pitch_deg (yaw 0 if absent)
  std::optional<double> speed_kmh;                // the vehicle's, when the row has one (>= 0)
  TurnIndicator indicator = TurnIndicator::none;  // none, left, right, both; empty cell or no column: none
};

struct FramesCsv {
  std::vector<std::string> truth_columns;  // every truth_* column, in file order
  std::vector<FrameRow> rows;              // the well-formed rows, in file order
  std::vector<double> truth;               // rows x truth_columns, NaN for an empty cell
  std::vector<std::string> issues;         // one "name:line: column: reason" per skipped row
  std::size_t data_rows = 0;               // rows in the file, well-formed or not
  bool has_gyro_columns = false;
  bool has_vehicle_columns = false;  // speed_kmh or turn_indicator
};

// Parses the text of a frames.csv; `name` prefixes messages. Blank lines and lines
// starting with '#' are ignored, other unknown columns too (e.g. a source_name). A
// malformed row (wrong field count, a number that is not one, an empty file name, time
// going backwards, a half gyro reading, a negative speed, an unknown indicator) is skipped and described in `issues`; a
// header without file or t_ns, or with a repeated column, throws FrameDirectoryError.
FramesCsv parse_frames_csv(std::string_view text, const std::string& name);

}  // namespace ccdlane
