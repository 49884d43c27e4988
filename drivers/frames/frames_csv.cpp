// frames.csv parsing: a strict reader that keeps every good row and names the bad ones.
#include "drivers/frames/frames_csv.hpp"

#include <charconv>
#include <cmath>
#include <limits>

namespace ccdlane {
namespace {

// Which angle of a gyro reading lies outside what the 3DM-GX1 reports (roll and yaw
// -180..180 degrees, pitch -90..90), or nullptr.
const char* gyro_out_of_range(const Gx1Angles& g) {
  if (!(std::abs(g.roll_deg) <= 180.0)) return "roll_deg: outside -180..180 degrees";
  if (!(std::abs(g.pitch_deg) <= 90.0)) return "pitch_deg: outside -90..90 degrees";
  if (!(std::abs(g.yaw_deg) <= 180.0)) return "yaw_deg: outside -180..180 degrees";
  return nullptr;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

void split(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

bool parse_int(std::string_view s, std::int64_t& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

bool parse_double(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty() && std::isfinite(out);
}

}  // namespace

FramesCsv parse_frames_csv(std::string_view text, const std::string& name) {
  FramesCsv csv;
  std::vector<std::string_view> fields;
  std::vector<std::string_view> header;
  int file_col = -1, t_col = -1, roll_col = -1, pitch_col = -1, yaw_col = -1, speed_col = -1, indicator_col = -1;
  std::vector<int> truth_cols;
  bool have_header = false;
  int line_no = 0;
  std::int64_t last_t = std::numeric_limits<std::int64_t>::min();

  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t nl = text.find('\n', pos);
    const std::string_view line = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
    pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
    ++line_no;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;

    if (!have_header) {
      have_header = true;
      split(content, header);
      for (std::size_t i = 0; i < header.size(); ++i) {
        const std::string_view h = header[i];
        for (std::size_t j = 0; j < i; ++j)
          if (header[j] == h)
            throw FrameDirectoryError(name + ":" + std::to_string(line_no) + ": column \"" + std::string(h) +
                                      "\" appears twice");
        const int col = static_cast<int>(i);
        if (h == "file")
          file_col = col;
        else if (h == "t_ns")
          t_col = col;
        else if (h == "roll_deg")
          roll_col = col;
        else if (h == "pitch_deg")
          pitch_col = col;
        else if (h == "yaw_deg")
          yaw_col = col;
        else if (h == "speed_kmh")
          speed_col = col;
        else if (h == "turn_indicator")
          indicator_col = col;
        else if (h.substr(0, 6) == "truth_") {
          truth_cols.push_back(col);
          csv.truth_columns.emplace_back(h);
        }
      }
      if (file_col < 0 || t_col < 0)
        throw FrameDirectoryError(name + ":" + std::to_string(line_no) + ": header needs the columns file and t_ns" +
                                  (file_col < 0 ? " (no file)" : " (no t_ns)"));
      if ((roll_col < 0) != (pitch_col < 0))
        throw FrameDirectoryError(name + ":" + std::to_string(line_no) +
                                  ": a gyro reading needs both roll_deg and pitch_deg columns");
      csv.has_gyro_columns = roll_col >= 0;
      csv.has_vehicle_columns = speed_col >= 0 || indicator_col >= 0;
      continue;
    }

    const std::size_t index = csv.data_rows++;
    auto issue = [&](const std::string& what) {
      csv.issues.push_back(name + ":" + std::to_string(line_no) + ": " + what);
    };
    split(content, fields);
    if (fields.size() != header.size()) {
      issue("row has " + std::to_string(fields.size()) + " fields, the header has " + std::to_string(header.size()));
      continue;
    }
    FrameRow row;
    row.index = index;
    row.line = line_no;
    row.file = std::string(fields[static_cast<std::size_t>(file_col)]);
    if (row.file.empty()) {
      issue("file: empty");
      continue;
    }
    const std::string_view t = fields[static_cast<std::size_t>(t_col)];
    if (!parse_int(t, row.t_ns)) {
      issue("t_ns: not an integer: \"" + std::string(t) + "\"");
      continue;
    }
    if (row.t_ns < last_t) {
      issue("t_ns: " + std::to_string(row.t_ns) + " goes back in time (previous frame " + std::to_string(last_t) + ")");
      continue;
    }
    bool bad = false;
    if (roll_col >= 0) {
      const std::string_view r = fields[static_cast<std::size_t>(roll_col)];
      const std::string_view p = fields[static_cast<std::size_t>(pitch_col)];
      const std::string_view y = yaw_col >= 0 ? fields[static_cast<std::size_t>(yaw_col)] : std::string_view();
      if (!r.empty() || !p.empty()) {  // an empty pair = no gyro reading at this frame
        Gx1Angles g;
        if (!parse_double(r, g.roll_deg)) {
          issue("roll_deg: not a number: \"" + std::string(r) + "\"");
          bad = true;
        } else if (!parse_double(p, g.pitch_deg)) {
          issue("pitch_deg: not a number: \"" + std::string(p) + "\"");
          bad = true;
        } else if (!y.empty() && !parse_double(y, g.yaw_deg)) {
          issue("yaw_deg: not a number: \"" + std::string(y) + "\"");
          bad = true;
        } else if (const char* range = gyro_out_of_range(g)) {
          // The 3DM-GX1 reports Euler angles in these ranges (its driver wraps them so):
          // anything else is damage, not a prior to weigh the solver with.
          issue(range);
          bad = true;
        }
        row.gyro = g;
      }
    }
    if (speed_col >= 0 && !bad) {
      const std::string_view v = fields[static_cast<std::size_t>(speed_col)];
      double speed = 0.0;
      if (!v.empty() && (!parse_double(v, speed) || speed < 0.0)) {
        issue("speed_kmh: not a speed >= 0: \"" + std::string(v) + "\"");
        bad = true;
      } else if (!v.empty()) {
        row.speed_kmh = speed;  // an empty cell: no speed known at this frame
      }
    }
    if (indicator_col >= 0 && !bad) {
      const std::string_view v = fields[static_cast<std::size_t>(indicator_col)];
      if (const auto indicator = v.empty() ? TurnIndicator::none : turn_indicator_from_string(v)) {
        row.indicator = *indicator;
      } else {
        issue("turn_indicator: not none, left, right or both: \"" + std::string(v) + "\"");
        bad = true;
      }
    }
    const std::size_t truth_start = csv.truth.size();
    for (std::size_t k = 0; k < truth_cols.size() && !bad; ++k) {
      const std::string_view v = fields[static_cast<std::size_t>(truth_cols[k])];
      double value = std::numeric_limits<double>::quiet_NaN();
      if (!v.empty() && !parse_double(v, value)) {
        issue(csv.truth_columns[k] + ": not a number: \"" + std::string(v) + "\"");
        bad = true;
      }
      csv.truth.push_back(value);
    }
    if (bad) {
      csv.truth.resize(truth_start);
      continue;
    }
    last_t = row.t_ns;
    csv.rows.push_back(std::move(row));
  }
  if (!have_header) throw FrameDirectoryError(name + ": empty (no header line)");
  return csv;
}

}  // namespace ccdlane
