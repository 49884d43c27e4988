// tools/measure-real as a user runs it, on the repository's ten TuSimple stills (a data
// folder without drives): each row it prints is what `ccdlane score` says of the replay
// it kept for that row, and each mount row replayed the configured camera moved as its
// name says (pitch and yaw by 5 degrees, the height by a quarter).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string kStills = std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple";
const std::string kMeasureReal = std::string(CCDLANE_SOURCE_DIR) + "/tools/measure-real";

std::string read_file(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The number a configuration file gives `key` (the first such line), NaN without one.
double toml_number(const std::string& path, const std::string& key) {
  std::smatch m;
  const std::string text = read_file(path);
  if (!std::regex_search(text, m, std::regex("(^|\n)" + key + R"( *= *([-+0-9.eE]+))"))) return std::nan("");
  return std::stod(m[2]);
}

// A row of the stills' table as printed, e.g. "nominal  10  70%  75.0%  65.9%  4.5%".
std::string printed_row(const std::string& out, const std::string& mount) {
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(mount + " ", 0) == 0) return line;
  return "";
}

// The same row from `ccdlane score` of the replay measure-real kept in `dir`.
std::string scored_row(const std::string& dir, const std::string& mount) {
  const test::ProcessResult s = test::run_process({CCDLANE_TOOL, "score", dir + "/camera.toml", dir + "/stills",
                                                   dir + "/stills.jsonl", kStills + "/labels.jsonl", "--json"});
  EXPECT_EQ(s.exit_status, 0) << s.err;
  const nlohmann::json t = nlohmann::json::parse(s.out)["total"];
  int frames = 0, ok = 0;
  std::istringstream replay(read_file(dir + "/stills.jsonl"));
  for (std::string line; std::getline(replay, line);) {
    ++frames;
    ok += nlohmann::json::parse(line)["ok"].get<bool>();
  }
  char row[160];
  std::snprintf(row, sizeof row, "%-14s %6d %5.0f%% %9.1f%% %8.1f%% %6.1f%%", mount.c_str(), frames,
                100.0 * ok / frames, 100.0 * t["ego_found"].get<double>() / t["ego_lanes"].get<double>(),
                100.0 * t["accuracy"].get<double>(),
                100.0 * t["false_lines"].get<double>() / std::max(1.0, t["reported_lines"].get<double>()));
  return row;
}

TEST(MeasureReal, EachStillsRowIsTheScoreOfItsReplayAtTheMountItNames) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), work = tmp.file("work");
  std::filesystem::create_directories(data);  // no drives/: the stills alone
  const test::ProcessResult r = test::run_process(
      {"python3", kMeasureReal, data, "--tusimple", kStills, "--ccdlane", CCDLANE_TOOL, "--keep", work});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("TuSimple stills, each picture alone"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("Drives"), std::string::npos) << "no drives in the data folder: no drives' table";

  const std::string nominal = work + "/tusimple/nominal/camera.toml";
  const double theta = toml_number(nominal, "theta_deg"), psi = toml_number(nominal, "psi_deg");
  const double height = toml_number(nominal, "H_mm");
  EXPECT_EQ(theta, toml_number(kStills + "/camera.toml", "theta_deg"));
  EXPECT_EQ(height, toml_number(kStills + "/camera.toml", "H_mm"));
  struct Row {
    std::string mount, dir;
    double theta, psi, height;
  };
  for (const Row& row :
       {Row{"nominal", "nominal", theta, psi, height}, Row{"pitch +5", "pitch_+5", theta + 5.0, psi, height},
        Row{"pitch -5", "pitch_-5", theta - 5.0, psi, height}, Row{"yaw +5", "yaw_+5", theta, psi + 5.0, height},
        Row{"yaw -5", "yaw_-5", theta, psi - 5.0, height},
        Row{"height x0.75", "height_x0.75", theta, psi, 0.75 * height},
        Row{"height x1.25", "height_x1.25", theta, psi, 1.25 * height}}) {
    const std::string dir = work + "/tusimple/" + row.dir;
    EXPECT_DOUBLE_EQ(toml_number(dir + "/camera.toml", "theta_deg"), row.theta) << row.mount;
    EXPECT_DOUBLE_EQ(toml_number(dir + "/camera.toml", "psi_deg"), row.psi) << row.mount;
    EXPECT_DOUBLE_EQ(toml_number(dir + "/camera.toml", "H_mm"), row.height) << row.mount;
    EXPECT_EQ(printed_row(r.out, row.mount), scored_row(dir, row.mount)) << r.out;
  }
}

}  // namespace
}  // namespace ccdlane
