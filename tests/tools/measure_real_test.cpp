// tools/measure-real as a user runs it, on the repository's share of the real data: its
// ten TuSimple stills (each row it prints is what `ccdlane score` says of the replay it
// kept for that row, and each mount row replayed the configured camera moved as its name
// says: pitch and yaw by 5 degrees, the height by a quarter) and its two Udacity drives
// (each row is its kept replay summed up again here, from the fourth second when the
// mount is off, and each drive's mount is calibrated).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/count_of.hpp"
#include "tests/support/json_lines.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string kStills = std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple";
const std::string kMeasureReal = std::string(CCDLANE_SOURCE_DIR) + "/tools/measure-real";

// The number a configuration file gives `key` (the first such line), NaN without one.
double toml_number(const std::string& path, const std::string& key) {
  std::smatch m;
  const std::string text = test::read_file(path);
  if (!std::regex_search(text, m, std::regex("(^|\n)" + key + R"( *= *([-+0-9.eE]+))"))) return std::nan("");
  return std::stod(m[2]);
}

// A row of the stills' table as printed, e.g.
// "nominal  10  70%  75.0%  65.9%  4.5%  40.0%   63.3% 0.133 0.442".
std::string printed_row(const std::string& out, const std::string& mount) {
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(mount + " ", 0) == 0) return line;
  return "";
}

// `ccdlane score` (JSON) of the replay measure-real kept in `dir`.
nlohmann::json score_json(const std::string& dir) {
  const test::ProcessResult s = test::run_process({CCDLANE_TOOL, "score", dir + "/camera.toml", dir + "/stills",
                                                   dir + "/stills.jsonl", kStills + "/labels.jsonl", "--json"});
  EXPECT_EQ(s.exit_status, 0) << s.err;
  return s.exit_status == 0 ? nlohmann::json::parse(s.out) : nlohmann::json::object();
}

// The same row from `ccdlane score` of the replay measure-real kept in `dir`, with
// TuSimple's own benchmark last.
std::string scored_row(const std::string& dir, const std::string& mount) {
  const nlohmann::json t = score_json(dir)["total"];
  int frames = 0, ok = 0;
  for (const nlohmann::json& e : test::json_lines(test::read_file(dir + "/stills.jsonl"))) {
    ++frames;
    ok += e["ok"].get<bool>();
  }
  const nlohmann::json& e = t["lane_eval"];  // TuSimple's own benchmark
  char row[200];
  const double next_found = (t["found"].get<double>() - t["ego_found"].get<double>()) /
                            std::max(1.0, t["lanes"].get<double>() - t["ego_lanes"].get<double>());
  std::snprintf(row, sizeof row, "%-14s %6d %5.0f%% %9.1f%% %8.1f%% %6.1f%% %9.1f%%   %12.1f%% %5.3f %5.3f",
                mount.c_str(), frames, 100.0 * ok / frames,
                100.0 * t["ego_found"].get<double>() / t["ego_lanes"].get<double>(),
                100.0 * t["accuracy"].get<double>(),
                100.0 * t["false_lines"].get<double>() / std::max(1.0, t["reported_lines"].get<double>()),
                100.0 * next_found, 100.0 * e["accuracy"].get<double>(), e["fp"].get<double>(), e["fn"].get<double>());
  return row;
}

TEST(MeasureReal, EachStillsRowIsTheScoreOfItsReplayAtTheMountItNames) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), work = tmp.file("work"), overlays = tmp.file("overlays");
  std::filesystem::create_directories(data);  // no drives/: the stills alone
  const test::ProcessResult r = test::run_process({"python3", kMeasureReal, data, "--tusimple", kStills, "--ccdlane",
                                                   CCDLANE_TOOL, "--keep", work, "--overlays", overlays});
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
  // The targets: the nominal row's three measures against their bounds, and in how many
  // of the six mount-off rows each is met, from the same scores.
  const auto measures = [&](const std::string& dir) {
    const nlohmann::json t = score_json(work + "/tusimple/" + dir)["total"];
    return std::array<double, 3>{t["ego_found"].get<double>() / t["ego_lanes"].get<double>(),
                                 t["accuracy"].get<double>(),
                                 t["false_lines"].get<double>() / std::max(1.0, t["reported_lines"].get<double>())};
  };
  const std::array<double, 3> bounds{0.95, 0.90, 0.05};
  const auto met = [&](const std::array<double, 3>& m, int k) { return k < 2 ? m[k] >= bounds[k] : m[k] <= bounds[k]; };
  const std::array<double, 3> at_nominal = measures("nominal");
  char line[300];
  std::snprintf(line, sizeof line,
                "stills, nominal mount        ego found %.2f %% >= 95 %%: %s; accuracy %.2f %% >= 90 %%: %s; "
                "false %.2f %% <= 5 %%: %s\n",
                100 * at_nominal[0], met(at_nominal, 0) ? "met" : "NOT met", 100 * at_nominal[1],
                met(at_nominal, 1) ? "met" : "NOT met", 100 * at_nominal[2], met(at_nominal, 2) ? "met" : "NOT met");
  EXPECT_NE(r.out.find(line), std::string::npos) << line << "not in\n" << r.out;
  std::array<int, 3> off_met{};
  for (const char* dir : {"pitch_+5", "pitch_-5", "yaw_+5", "yaw_-5", "height_x0.75", "height_x1.25"})
    for (int k = 0; k < 3; ++k) off_met[static_cast<std::size_t>(k)] += met(measures(dir), k);
  std::snprintf(line, sizeof line, "6 rows, each target met in: ego found %d, accuracy %d, false %d\n", off_met[0],
                off_met[1], off_met[2]);
  EXPECT_NE(r.out.find(line), std::string::npos) << line << "not in\n" << r.out;

  // The nominal row's stills to look at, one per still, named by its frame number.
  for (int i = 0; i < 10; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "/%06d.png", i);
    EXPECT_TRUE(std::filesystem::is_regular_file(overlays + name)) << name;
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(overlays), std::filesystem::directory_iterator{}), 10);
}

// The frame count a printed stills' row gives (0 without the row).
int row_frames(const std::string& out, const std::string& mount) {
  std::istringstream row(printed_row(out, mount));
  std::string name;
  int frames = 0;
  row >> name >> frames;
  return frames;
}

// measure-real --misses on the stills of `folder` alone (`data`: an empty data folder), at
// the nominal mount only: what these tests look at (how the stills are found and read)
// is the same in every row.
test::ProcessResult measure_stills_with_misses(const std::string& data, const std::string& folder) {
  return test::run_process(
      {"python3", kMeasureReal, data, "--tusimple", folder, "--ccdlane", CCDLANE_TOOL, "--misses", "--nominal-only"});
}

// A stills' folder as users keep one: a note and a folder (here a link to the pictures'
// own folder, as a misplaced `ln -s` makes) beside the pictures. Only the pictures are
// stills: the rows count ten frames, as for the folder without them.
TEST(MeasureReal, OnlyThePicturesOfTheImagesFolderAreStills) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), stills = tmp.file("stills");
  std::filesystem::create_directories(data);
  std::filesystem::copy(kStills, stills, std::filesystem::copy_options::recursive);
  std::ofstream(stills + "/images/README.txt") << "frames 0000-0009 of the TuSimple development set\n";
  std::filesystem::create_directory_symlink(stills + "/images", stills + "/images/images");
  const test::ProcessResult r = measure_stills_with_misses(data, stills);
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  EXPECT_EQ(row_frames(r.out, "nominal"), 10) << r.out;
}

// A still whose picture is cut short stays in every row (nothing found in it, as
// replay reports it) and is named once below the table with replay's cause; the exit
// status says not everything was measured.
TEST(MeasureReal, AStillThatCannotBeReadIsNamedWithItsCause) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), stills = tmp.file("stills");
  std::filesystem::create_directories(data);
  std::filesystem::copy(kStills, stills, std::filesystem::copy_options::recursive);
  const std::string picture = test::read_file(stills + "/images/0003.jpg");
  std::filesystem::remove(stills + "/images/0003.jpg");
  std::ofstream(stills + "/images/0003.jpg", std::ios::binary) << picture.substr(0, picture.size() / 3);
  const test::ProcessResult r = measure_stills_with_misses(data, stills);
  EXPECT_EQ(r.exit_status, 1) << r.out << r.err;
  EXPECT_EQ(row_frames(r.out, "nominal"), 10) << r.out;
  EXPECT_NE(r.out.find("stills whose pictures could not be read (in each row as stills where nothing was found): 1: "
                       "0003.jpg (truncated"),
            std::string::npos)
      << r.out;
}

// The ten stills labelled as CULane labels its pictures (NAME.lines.txt beside NAME.jpg,
// "x y x y ..." per lane, 0-based), from their TuSimple labels point for point: the row,
// and the --misses list, is what the TuSimple labels give. TuSimple's own benchmark
// needs its rows (h_samples), which CULane's labels do not name: "-".
TEST(MeasureReal, StillsWithCULaneLabelsMeasureAsWithTheSameTuSimpleLabels) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), stills = tmp.file("culane");
  std::filesystem::create_directories(data);
  std::filesystem::create_directories(stills + "/images");
  std::filesystem::copy_file(kStills + "/camera.toml", stills + "/camera.toml");
  int labelled = 0;
  for (const nlohmann::json& l : test::json_lines(test::read_file(kStills + "/labels.jsonl"))) {
    const std::filesystem::path image = l["image"].get<std::string>();
    std::filesystem::copy_file(kStills + "/" + image.string(), stills + "/images/" + image.filename().string());
    std::ofstream lines(stills + "/images/" + image.stem().string() + ".lines.txt");
    for (const auto& lane : l["lanes"]) {
      std::string text;
      for (std::size_t i = 0; i < lane.size(); ++i)
        if (lane[i].get<int>() >= 0)
          text += std::to_string(lane[i].get<int>()) + " " + std::to_string(l["h_samples"][i].get<int>()) + " ";
      if (!text.empty()) lines << text << "\n";
    }
    ++labelled;
  }
  ASSERT_EQ(labelled, 10);
  const test::ProcessResult tusimple = measure_stills_with_misses(data, kStills),
                            culane = measure_stills_with_misses(data, stills);
  ASSERT_EQ(tusimple.exit_status, 0) << tusimple.out << tusimple.err;
  ASSERT_EQ(culane.exit_status, 0) << culane.out << culane.err;
  EXPECT_NE(culane.out.find("Stills (CULane labels), each picture alone"), std::string::npos) << culane.out;
  const std::string want = printed_row(tusimple.out, "nominal"), got = printed_row(culane.out, "nominal");
  ASSERT_FALSE(want.empty()) << tusimple.out;
  // Mount, frames, ok, ego found, accuracy, false and next found: the first 68 columns.
  EXPECT_EQ(got.substr(0, 68), want.substr(0, 68));
  EXPECT_EQ(got.substr(68, 28), "               -     -     -") << got;
  const std::string misses = "Nominal row, the stills that lost an own line or reported a false one\n";
  ASSERT_NE(tusimple.out.find(misses), std::string::npos) << tusimple.out;
  const auto misses_of = [&](const std::string& out) {
    const std::size_t from = out.find(misses);
    return out.substr(from);
  };
  EXPECT_EQ(misses_of(culane.out), misses_of(tusimple.out));
}

// The ten stills laid out as TuSimple publishes its frames: each picture at the path its
// label's "raw_file" names (clips/<clip>/<n>/20.jpg, one name for every picture), no
// images/ folder. The stills are the pictures the labels name, in the labels' order,
// and measure as the same pictures in images/ do.
TEST(MeasureReal, StillsInTuSimplesOwnLayoutAreThePicturesTheirLabelsName) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), stills = tmp.file("clips_layout");
  std::filesystem::create_directories(data);
  std::filesystem::create_directories(stills);
  std::filesystem::copy_file(kStills + "/camera.toml", stills + "/camera.toml");
  std::ofstream labels(stills + "/labels.jsonl");
  int n = 0;
  for (nlohmann::json l : test::json_lines(test::read_file(kStills + "/labels.jsonl"))) {
    const std::string raw_file = "clips/0313-1/" + std::to_string(6000 + 20 * n++) + "/20.jpg";
    std::filesystem::create_directories(std::filesystem::path(stills + "/" + raw_file).parent_path());
    std::filesystem::copy_file(kStills + "/" + l["image"].get<std::string>(), stills + "/" + raw_file);
    l.erase("image");
    l["raw_file"] = raw_file;
    labels << l.dump() << "\n";
  }
  labels.close();
  ASSERT_EQ(n, 10);
  const test::ProcessResult images = measure_stills_with_misses(data, kStills),
                            clips = measure_stills_with_misses(data, stills);
  ASSERT_EQ(images.exit_status, 0) << images.out << images.err;
  ASSERT_EQ(clips.exit_status, 0) << clips.out << clips.err;
  const std::string want = printed_row(images.out, "nominal");
  ASSERT_FALSE(want.empty()) << images.out;
  EXPECT_EQ(printed_row(clips.out, "nominal"), want);
  // The misses name each still by its path below the clips, not by the name all share.
  const std::size_t from = clips.out.find("Nominal row, the stills that lost an own line");
  ASSERT_NE(from, std::string::npos) << clips.out;
  std::istringstream misses(clips.out.substr(from));
  std::string line;
  std::getline(misses, line), std::getline(misses, line);  // the title and the columns' heads
  int listed = 0;
  for (; std::getline(misses, line) && line.rfind("false lines by", 0) != 0; ++listed)
    EXPECT_TRUE(std::regex_search(line, std::regex(R"(^ +\d+ \d{4}/20\.jpg +\d/\d)"))) << line;
  EXPECT_GT(listed, 0) << clips.out;
}

// A stills' folder without labels is said to be one, and not measured; with no drives
// either, there was nothing to measure, and the exit status says so.
TEST(MeasureReal, StillsWithoutLabelsAreNotMeasuredAndSaySo) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), stills = tmp.file("stills");
  std::filesystem::create_directories(data);
  std::filesystem::copy(kStills, stills, std::filesystem::copy_options::recursive);
  std::filesystem::remove(stills + "/labels.jsonl");
  const test::ProcessResult r =
      test::run_process({"python3", kMeasureReal, data, "--tusimple", stills, "--ccdlane", CCDLANE_TOOL});
  EXPECT_EQ(r.exit_status, 1) << r.out << r.err;
  EXPECT_NE(r.out.find(stills + ": no labels (labels.jsonl, or NAME.lines.txt beside each picture)"), std::string::npos)
      << r.out;
  EXPECT_EQ(printed_row(r.out, "nominal"), "") << r.out;
  EXPECT_NE(r.err.find(data + ": nothing to measure: no labelled stills in " + stills), std::string::npos) << r.err;
}

// A stills' or drives' folder without its camera.toml is said to lack one, and not
// measured (no Python traceback); the exit status says not everything was measured.
TEST(MeasureReal, AFolderWithoutItsCameraFileSaysSo) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), stills = tmp.file("stills"), drives = tmp.file("drives");
  std::filesystem::create_directories(data);
  std::filesystem::copy(kStills, stills, std::filesystem::copy_options::recursive);
  std::filesystem::remove(stills + "/camera.toml");
  std::filesystem::create_directories(drives);
  std::filesystem::copy_file(std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-drives/project_video_segA.mp4",
                             drives + "/segA.mp4");
  const test::ProcessResult r = test::run_process(
      {"python3", kMeasureReal, data, "--tusimple", stills, "--drives", drives, "--ccdlane", CCDLANE_TOOL});
  EXPECT_EQ(r.exit_status, 1) << r.out << r.err;
  EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find(stills + ": no camera.toml beside the stills"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(drives + ": no camera.toml beside the drives"), std::string::npos) << r.out;
  EXPECT_EQ(printed_row(r.out, "nominal"), "") << r.out;
}

// A mistyped folder is a usage error, not an empty table that exits 0.
TEST(MeasureReal, AFolderThatIsNotThereIsAUsageError) {
  test::TempDir tmp;
  const test::ProcessResult r =
      test::run_process({"python3", kMeasureReal, tmp.file("not-there"), "--ccdlane", CCDLANE_TOOL});
  EXPECT_EQ(r.exit_status, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(tmp.file("not-there") + ": no such folder"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

// --help says how DATA_DIR is laid out (each layout the stills may come in) and what the
// exit status means, not only the flags.
TEST(MeasureReal, HelpSaysHowTheDataFolderIsLaidOut) {
  const test::ProcessResult r = test::run_process({"python3", kMeasureReal, "--help"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  for (const char* said : {"tusimple/images/*.jpg", "\"raw_file\"", "NAME.lines.txt", "drives/*.mp4", "Exit status"})
    EXPECT_NE(r.out.find(said), std::string::npos) << said << " not in\n" << r.out;
}

// Its replays (20 MB a run) go into a temporary folder that is removed when it ends,
// however it ends (here: with nothing to measure), unless --keep names a folder for them.
TEST(MeasureReal, LeavesNoReplaysBehindUnlessAskedToKeepThem) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), temp = tmp.file("tmp"), kept = tmp.file("kept");
  std::filesystem::create_directories(data + "/tusimple");
  std::filesystem::create_directories(temp);
  std::filesystem::copy(kStills + "/camera.toml", data + "/tusimple/camera.toml");
  const auto measure = [&](std::vector<std::string> more) {
    std::vector<std::string> argv{"env", "TMPDIR=" + temp, "python3", kMeasureReal, data, "--ccdlane", CCDLANE_TOOL};
    argv.insert(argv.end(), more.begin(), more.end());
    return test::run_process(argv);
  };
  const test::ProcessResult r = measure({});
  ASSERT_EQ(r.exit_status, 1) << r.out << r.err;
  EXPECT_TRUE(std::filesystem::is_empty(temp));
  const test::ProcessResult k = measure({"--keep", kept});
  ASSERT_EQ(k.exit_status, 1) << k.out << k.err;
  EXPECT_TRUE(std::filesystem::is_directory(kept));
}

// Where a false line leaves its lane, by the rule --misses states: the third of the
// still's labelled rows (first to last row any lane is labelled on) most of its rows off
// a lane lie in.
std::string where_off(const std::vector<int>& off, int first_row, int last_row) {
  const double third = (last_row - first_row) / 3.0;
  std::size_t near = 0, far = 0;
  for (const int r : off) near += r > last_row - third, far += r < first_row + third;
  if (2 * near > off.size()) return "near the car";
  if (2 * far > off.size()) return "far";
  return "along";
}

// measure-real on the repository's ten stills alone (an empty data folder: no drives),
// its replays kept in `work`, with `options` added.
test::ProcessResult measure_ten_stills(const test::TempDir& tmp, const std::string& work,
                                       const std::vector<std::string>& options) {
  const std::string data = tmp.file("data");
  std::filesystem::create_directories(data);
  std::vector<std::string> argv{"python3",   kMeasureReal, data,     "--tusimple", kStills,
                                "--ccdlane", CCDLANE_TOOL, "--keep", work};
  argv.insert(argv.end(), options.begin(), options.end());
  return test::run_process(argv);
}

// The line --misses prints of where the lost own lines' lines miss them, from `ccdlane
// score`'s JSON of the nominal row: each own lane not found, by the line that hits most of
// its points (none: "no line") and whether most of the rows that line misses lie below
// the row of its nearest mark ("beyond its marks") or not ("along its marks").
std::string lost_own_summary(const nlohmann::json& scored) {
  int beyond = 0, along = 0, no_line = 0;
  for (const nlohmann::json& f : scored["frames"])
    for (const nlohmann::json& lane : f["lane_results"]) {
      if (!lane["ego"].get<bool>() || lane["found"].get<bool>()) continue;
      if (lane["line"].is_null()) {
        ++no_line;
        continue;
      }
      const nlohmann::json& nearest = f["line_results"][lane["line"].get<std::size_t>()]["nearest_mark_row"];
      const std::vector<int> missed = lane["missed_rows"].get<std::vector<int>>();
      const auto below = std::count_if(missed.begin(), missed.end(),
                                       [&](int row) { return nearest.is_number() && row > nearest.get<double>(); });
      (2 * below > static_cast<long>(missed.size()) ? beyond : along) += 1;
    }
  return "own lines lost by where their line misses them: beyond its marks " + std::to_string(beyond) +
         ", along its marks " + std::to_string(along) + ", no line " + std::to_string(no_line) + " (of " +
         std::to_string(beyond + along + no_line) + ")\n";
}

// --misses lists, of the nominal row, exactly the stills `ccdlane score` says lost an own
// line or reported a false one, with their own lines found, each false line's points on
// a lane and where it leaves it; and the stills at least half of the rows lost an own
// line in.
TEST(MeasureReal, TheMissesAreTheNominalRowsStillsThatLostAnOwnLineOrReportedAFalseOne) {
  test::TempDir tmp;
  const std::string work = tmp.file("work");
  const test::ProcessResult r = measure_ten_stills(tmp, work, {"--misses"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  const std::size_t list = r.out.find("Nominal row, the stills that lost an own line or reported a false one\n");
  ASSERT_NE(list, std::string::npos) << r.out;

  std::map<std::string, std::pair<int, int>> rows;  // image -> first and last labelled row
  for (const nlohmann::json& l : test::json_lines(test::read_file(kStills + "/labels.jsonl"))) {
    int first = 1 << 20, last = -1;
    for (const auto& lane : l["lanes"])
      for (std::size_t i = 0; i < lane.size(); ++i)
        if (lane[i].get<int>() >= 0)
          first = std::min(first, l["h_samples"][i].get<int>()), last = std::max(last, l["h_samples"][i].get<int>());
    rows[std::filesystem::path(l["image"].get<std::string>()).filename().string()] = {first, last};
  }
  std::string expected;
  int false_lines = 0, listed = 0;
  const nlohmann::json nominal = score_json(work + "/tusimple/nominal");
  for (const nlohmann::json& f : nominal["frames"]) {
    std::vector<std::string> falses;
    const std::string file = std::filesystem::path(f["file"].get<std::string>()).filename().string();
    for (const nlohmann::json& l : f["line_results"]) {
      if (!l["false"].get<bool>()) continue;
      const std::vector<int> off = l["off_rows"].get<std::vector<int>>();
      ASSERT_FALSE(off.empty()) << "a false line is off its lane somewhere";
      falses.push_back("line " + std::to_string(l["line"].get<int>()) + ": " +
                       std::to_string(l["on_lane_points"].get<int>()) + " of " +
                       std::to_string(l["points"].get<int>()) + ", " +
                       where_off(off, rows.at(file).first, rows.at(file).second) + ", rows " +
                       std::to_string(*std::min_element(off.begin(), off.end())) + "-" +
                       std::to_string(*std::max_element(off.begin(), off.end())));
    }
    const int own = f["ego_found"].get<int>(), labelled = f["ego_lanes"].get<int>();
    if (own == labelled && falses.empty()) continue;
    false_lines += static_cast<int>(falses.size());
    ++listed;
    std::string joined;
    for (const std::string& x : falses) joined += (joined.empty() ? "" : "; ") + x;
    char row[400];
    std::snprintf(row, sizeof row, "%5d %-20s %2d/%-2d  %s\n", f["frame"].get<int>(), file.c_str(), own, labelled,
                  joined.empty() ? "-" : joined.c_str());
    expected += row;
  }
  ASSERT_GT(listed, 0) << "the ten stills lose or add a line somewhere: the list has something to show";
  const std::size_t body = r.out.find('\n', r.out.find('\n', list) + 1) + 1;  // after the title and header
  EXPECT_EQ(r.out.substr(body, expected.size()), expected) << r.out;
  EXPECT_NE(r.out.find("(of " + std::to_string(false_lines) + ")\n", body), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(lost_own_summary(nominal), body), std::string::npos) << r.out;

  // The stills lost in at least half of the mount rows measured (each a kept replay; the
  // jittered pictures' replays, condition_*, are other pictures, not other mounts).
  std::map<int, int> lost;
  int measured = 0;
  for (const auto& dir : std::filesystem::directory_iterator(work + "/tusimple")) {
    if (!std::filesystem::is_regular_file(dir.path() / "stills.jsonl") ||
        dir.path().filename().string().rfind("condition_", 0) == 0)
      continue;
    ++measured;
    const nlohmann::json scored = score_json(dir.path().string());
    for (const nlohmann::json& f : scored["frames"])
      lost[f["frame"].get<int>()] += f["ego_found"].get<int>() < f["ego_lanes"].get<int>();
  }
  std::string often;
  for (const auto& [frame, n] : lost)
    if (2 * n >= measured) often += (often.empty() ? "" : ", ") + std::to_string(frame);
  EXPECT_NE(r.out.find("stills that lost an own line in at least half of the " + std::to_string(measured) +
                       " rows: " + (often.empty() ? "none" : often) + "\n"),
            std::string::npos)
      << r.out;
}

// An own lane whose labelled points below its line's nearest mark are moved 150 px out
// (as a lane would run that bends away where the line is only drawn on from its farther
// marks) is lost "beyond its marks", and only those: --misses counts each such lane
// there, and nothing else moves.
TEST(MeasureReal, AnOwnLaneLostBelowItsLinesNearestMarkIsLostBeyondItsMarks) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), stills = tmp.file("stills"), work = tmp.file("work");
  std::filesystem::create_directories(data);
  std::filesystem::copy(kStills, stills, std::filesystem::copy_options::recursive);
  const auto measure = [&](const std::string& keep) {
    return test::run_process({"python3", kMeasureReal, data, "--tusimple", stills, "--ccdlane", CCDLANE_TOOL,
                              "--misses", "--nominal-only", "--keep", keep});
  };
  const test::ProcessResult before = measure(work);
  ASSERT_EQ(before.exit_status, 0) << before.out << before.err;
  const nlohmann::json scored = score_json(work + "/tusimple/nominal");

  // Per still (in the labels' order), the own lanes found whose line's nearest mark lies
  // above a fifth or more of their points: those points are moved.
  std::vector<nlohmann::json> labels = test::json_lines(test::read_file(stills + "/labels.jsonl"));
  int moved = 0;
  for (const nlohmann::json& f : scored["frames"]) {
    nlohmann::json& label = labels.at(f["frame"].get<std::size_t>());
    for (const nlohmann::json& lane : f["lane_results"]) {
      if (!lane["ego"].get<bool>() || !lane["found"].get<bool>() || lane["line"].is_null()) continue;
      const nlohmann::json& nearest = f["line_results"][lane["line"].get<std::size_t>()]["nearest_mark_row"];
      if (!nearest.is_number()) continue;
      auto& xs = label["lanes"][lane["level"].get<std::size_t>() - 1];
      const auto& rows = label["h_samples"];
      int points = 0, below = 0;
      for (std::size_t i = 0; i < xs.size(); ++i)
        if (xs[i].get<int>() >= 0) ++points, below += rows[i].get<int>() + 1 > nearest.get<double>();
      if (5 * below < points) continue;
      const int out = lane["x_bottom_px"].get<double>() < 640.0 ? -150 : 150;
      for (std::size_t i = 0; i < xs.size(); ++i)
        if (xs[i].get<int>() >= 0 && rows[i].get<int>() + 1 > nearest.get<double>())
          xs[i] = std::max(0, xs[i].get<int>() + out);
      ++moved;
    }
  }
  ASSERT_GT(moved, 0) << "some own line of the ten stills is drawn on below its nearest mark";
  std::ofstream rewritten(stills + "/labels.jsonl");
  for (const nlohmann::json& l : labels) rewritten << l.dump() << "\n";
  rewritten.close();

  const test::ProcessResult after = measure(tmp.file("work-after"));
  ASSERT_EQ(after.exit_status, 0) << after.out << after.err;
  const std::regex summary(R"(own lines lost by where their line misses them: beyond its marks (\d+), along its )"
                           R"(marks (\d+), no line (\d+) \(of (\d+)\))");
  std::smatch was, is;
  ASSERT_TRUE(std::regex_search(before.out, was, summary)) << before.out;
  ASSERT_TRUE(std::regex_search(after.out, is, summary)) << after.out;
  EXPECT_EQ(std::stoi(is[1]), std::stoi(was[1]) + moved) << after.out;
  EXPECT_EQ(is[2], was[2]);
  EXPECT_EQ(is[3], was[3]);
  EXPECT_EQ(std::stoi(is[4]), std::stoi(was[4]) + moved);
}

// --conditions: each row is the score of the stills replayed with its condition at the
// nominal mount (the kept replay is what `ccdlane replay --condition` gives, line for line),
// printed as the stills' rows are, without the frame count and TuSimple's own figures.
TEST(MeasureReal, EachConditionRowIsTheScoreOfTheStillsReplayedSoAtTheNominalMount) {
  test::TempDir tmp;
  const std::string work = tmp.file("work");
  const test::ProcessResult r = measure_ten_stills(tmp, work, {"--conditions", "--nominal-only"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  ASSERT_NE(r.out.find("Stills as other cameras and light give them"), std::string::npos) << r.out;
  const std::string nominal = work + "/tusimple/nominal/camera.toml";
  const std::vector<std::pair<std::string, std::string>> conditions = {
      {"blur 1 px", "blur=1"},
      {"blur 1.5 px", "blur=1.5"},
      {"light x0.5", "light=0.5"},
      {"light x0.3", "light=0.3"},
      {"light x0.3 noise 3", "light=0.3,noise=3"},
      {"noise 6", "noise=6"},
      {"shade x0.3 near", "shade=0.3"},
      {"shade x0.3 far", "shade=0.3,shade_top=0.45,shade_bottom=0.6"},
      {"dapple x0.4", "dapple=0.4"},
      {"jpeg q75", "jpeg=75"},
      {"pixels x1.5", "scale=1.5"},
      {"pixels x0.5", "scale=0.5"}};
  std::set<std::string> rows;
  for (const auto& [name, condition] : conditions) {
    std::string dir_name = "condition_" + condition;
    dir_name.erase(std::remove(dir_name.begin(), dir_name.end(), '='), dir_name.end());
    std::replace(dir_name.begin(), dir_name.end(), ',', '_');
    const std::string dir = work + "/tusimple/" + dir_name;
    const test::ProcessResult again =
        test::run_process({CCDLANE_TOOL, "replay", nominal, dir + "/stills", "--stills", "--condition", condition});
    ASSERT_EQ(again.exit_status, 0) << again.err;
    EXPECT_EQ(test::json_lines_without_latency(test::read_file(dir + "/stills.jsonl")),
              test::json_lines_without_latency(again.out))
        << name;
    // The stills' row less its frame count and TuSimple's own figures, under this name.
    const std::string full = scored_row(dir, "-");
    std::istringstream fields(full.substr(14));
    std::string frames, ok, ego, accuracy, false_share, next;
    fields >> frames >> ok >> ego >> accuracy >> false_share >> next;
    char row[200];
    std::snprintf(row, sizeof row, "%-20s %6s %10s %9s %7s %10s", name.c_str(), ok.c_str(), ego.c_str(),
                  accuracy.c_str(), false_share.c_str(), next.c_str());
    EXPECT_EQ(printed_row(r.out, name), row) << r.out;
    rows.insert(row);
  }
  EXPECT_GT(rows.size(), 1u) << "the conditions change what is found: the rows differ";
}

// Every run also replays the nominal stills four times more, each picture changed less
// than a camera changes it from frame to frame; the "jittered" row is those four replays'
// scores summed (each kept replay is what `ccdlane replay --condition` gives), and the
// targets hold it to the nominal row's bounds.
TEST(MeasureReal, TheJitteredRowSumsTheNominalStillsReplayedWithFourSmallChanges) {
  test::TempDir tmp;
  const std::string work = tmp.file("work");
  const test::ProcessResult r = measure_ten_stills(tmp, work, {"--misses"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  const std::string nominal = work + "/tusimple/nominal/camera.toml";
  const auto recorded = test::json_lines_without_latency(test::read_file(work + "/tusimple/nominal/stills.jsonl"));
  std::map<std::string, double> sum;
  int frames = 0, ok = 0;
  for (const auto& [condition, dir_name] :
       {std::pair{"light=0.97", "condition_light0.97"}, std::pair{"light=1.03", "condition_light1.03"},
        std::pair{"noise=1", "condition_noise1"}, std::pair{"blur=0.4", "condition_blur0.4"}}) {
    const std::string dir = work + "/tusimple/" + dir_name;
    const test::ProcessResult again =
        test::run_process({CCDLANE_TOOL, "replay", nominal, dir + "/stills", "--stills", "--condition", condition});
    ASSERT_EQ(again.exit_status, 0) << again.err;
    const auto kept = test::json_lines_without_latency(test::read_file(dir + "/stills.jsonl"));
    EXPECT_EQ(kept, test::json_lines_without_latency(again.out)) << condition;
    EXPECT_NE(kept, recorded) << condition << ": the pictures were changed, and so is what was estimated from them";
    const nlohmann::json t = score_json(dir)["total"];
    for (const char* key :
         {"ego_found", "ego_lanes", "hit_points", "points", "false_lines", "reported_lines", "found", "lanes"})
      sum[key] += t[key].get<double>();
    for (const nlohmann::json& e : kept) {
      ++frames;
      ok += e["ok"].get<bool>();
    }
  }
  ASSERT_EQ(frames, 40);
  const double ego = sum["ego_found"] / sum["ego_lanes"], accuracy = sum["hit_points"] / sum["points"];
  const double false_share = sum["false_lines"] / std::max(1.0, sum["reported_lines"]);
  char row[200];
  std::snprintf(row, sizeof row, "%-14s %6d %5.0f%% %9.1f%% %8.1f%% %6.1f%% %9.1f%%   (the nominal row 4 times",
                "jittered", frames, 100.0 * ok / frames, 100.0 * ego, 100.0 * accuracy, 100.0 * false_share,
                100.0 * (sum["found"] - sum["ego_found"]) / std::max(1.0, sum["lanes"] - sum["ego_lanes"]));
  EXPECT_EQ(printed_row(r.out, "jittered").rfind(row, 0), 0u) << row << "\nnot the start of a row of\n" << r.out;
  char line[300];
  std::snprintf(line, sizeof line,
                "stills, nominal, jittered    ego found %.2f %% >= 95 %%: %s; accuracy %.2f %% >= 90 %%: %s; "
                "false %.2f %% <= 5 %%: %s\n",
                100 * ego, ego >= 0.95 ? "met" : "NOT met", 100 * accuracy, accuracy >= 0.90 ? "met" : "NOT met",
                100 * false_share, false_share <= 0.05 ? "met" : "NOT met");
  EXPECT_NE(r.out.find(line), std::string::npos) << line << "not in\n" << r.out;
}

// --held replays each still 60 times in a row (one picture, frames 40 ms apart: a car
// standing still) and its line is what those replays say: the stills ok on each of the
// last 20 frames, the share of frames ok, the others by number.
TEST(MeasureReal, EachHeldStillIsOnePictureReplayedSixtyTimesAndCountedByItsReplay) {
  test::TempDir tmp;
  const std::string work = tmp.file("work");
  const test::ProcessResult r = measure_ten_stills(tmp, work, {"--held", "--nominal-only"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(kStills + "/images"))
    names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  ASSERT_EQ(names.size(), 10u);
  int steady = 0, ok = 0, frames = 0;
  std::string unsteady;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string held = work + "/tusimple/held/" + names[i];
    std::istringstream csv(test::read_file(held + "/frames.csv"));
    std::string line;
    std::getline(csv, line);  // header
    int listed = 0;
    for (; std::getline(csv, line); ++listed) {
      EXPECT_NE(line.find("/" + names[i] + ".jpg,"), std::string::npos) << line;
      EXPECT_EQ(line.substr(line.find(',') + 1), std::to_string(listed * 40000000LL)) << line;
    }
    EXPECT_EQ(listed, 60) << held;
    std::vector<bool> oks;
    for (const nlohmann::json& e : test::json_lines(test::read_file(held + ".jsonl")))
      oks.push_back(e["ok"].get<bool>());
    ASSERT_EQ(oks.size(), 60u) << held;
    frames += 60;
    ok += static_cast<int>(std::count(oks.begin(), oks.end(), true));
    if (std::all_of(oks.end() - 20, oks.end(), [](bool b) { return b; }))
      ++steady;
    else
      unsteady += (unsteady.empty() ? "" : ", ") + std::to_string(i);
  }
  char expected[300];
  std::snprintf(expected, sizeof expected,
                "steady (ok on each of the last 20 frames): %d of 10; frames ok %.1f%%; not steady: %s\n", steady,
                100.0 * ok / frames, unsteady.empty() ? "none" : unsteady.c_str());
  EXPECT_NE(r.out.find(expected), std::string::npos) << expected << "not in\n" << r.out;
  EXPECT_LT(ok, frames) << "the ten stills held are not all ok: the count has something to show";
}

// Without --ccdlane (nor CCDLANE), measure-real takes the ccdlane the README's commands
// built in its checkout: build/ci's (tools/run-tests) or build/demo's (tools/run-demo, the
// main command). With neither, it says where it looked and what builds one.
TEST(MeasureReal, FindsTheDemosBuildAndSaysWhatToRunWithoutOne) {
  test::TempDir tmp;
  const std::string checkout = tmp.file("checkout"), data = tmp.file("data");
  std::filesystem::create_directories(checkout + "/tools");
  std::filesystem::create_directories(data);
  std::filesystem::copy_file(kMeasureReal, checkout + "/tools/measure-real");
  const std::vector<std::string> measure = {
      "env", "-u",         "CCDLANE", "python3",       checkout + "/tools/measure-real",
      data,  "--tusimple", kStills,   "--nominal-only"};
  bool on_path = false;
  std::istringstream path(std::getenv("PATH") ? std::getenv("PATH") : "");
  for (std::string dir; std::getline(path, dir, ':');) on_path = on_path || std::filesystem::exists(dir + "/ccdlane");
  if (!on_path) {
    const test::ProcessResult none = test::run_process(measure);
    EXPECT_EQ(none.exit_status, 1);
    EXPECT_NE(none.err.find(checkout + "/build/demo/tools/ccdlane"), std::string::npos) << none.err;
    EXPECT_NE(none.err.find("tools/run-demo"), std::string::npos) << none.err;
    EXPECT_NE(none.err.find("--ccdlane PATH"), std::string::npos) << none.err;
  }
  std::filesystem::create_directories(checkout + "/build/demo/tools");
  std::filesystem::create_symlink(CCDLANE_TOOL, checkout + "/build/demo/tools/ccdlane");
  const test::ProcessResult r = test::run_process(measure);
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("TuSimple stills, each picture alone"), std::string::npos) << r.out;
  if (on_path) GTEST_SKIP() << "a ccdlane on PATH: the case without one is not seen here";
}

// A drive's row recomputed from the replay measure-real kept: frames from `from_s` on,
// the share ok, the ok frames' lane width (mean, m, and sd over the mean), the median
// change of the lateral offset between consecutive ok frames, and the warnings fired.
// `mount` is printed `width` wide (a condition's name: 20).
struct DriveMeasures {
  std::size_t frames = 0;
  double ok = 0.0, width_mm = 0.0, width_sd = 0.0, step_mm = 0.0;
  int warnings = 0;
  bool meets_targets() const { return ok >= 0.98 && width_sd <= 0.02 && step_mm <= 30.0 && warnings == 0; }
};

DriveMeasures drive_measures(const std::string& replay, double from_s) {
  std::vector<nlohmann::json> kept = test::json_lines(test::read_file(replay));
  if (kept.empty()) return {};
  const auto t0 = kept.front()["t_ns"].get<std::int64_t>();
  std::erase_if(kept, [&](const nlohmann::json& e) {
    return static_cast<double>(e["t_ns"].get<std::int64_t>() - t0) < from_s * 1e9;
  });
  std::vector<double> widths, steps;
  int warnings = 0;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (kept[i]["ok"].get<bool>()) widths.push_back(kept[i]["lane_width_mm"].get<double>());
    if (i > 0 && kept[i]["ok"].get<bool>() && kept[i - 1]["ok"].get<bool>())
      steps.push_back(
          std::abs(kept[i]["lateral_offset_mm"].get<double>() - kept[i - 1]["lateral_offset_mm"].get<double>()));
    warnings += kept[i]["ldw"]["fired"].get<std::string>() != "none";
  }
  double mean = 0.0, var = 0.0;
  for (const double w : widths) mean += w / static_cast<double>(widths.size());
  for (const double w : widths) var += (w - mean) * (w - mean) / static_cast<double>(widths.size());
  std::sort(steps.begin(), steps.end());
  const std::size_t n = steps.size();
  const double median = n % 2 ? steps[n / 2] : 0.5 * (steps[n / 2 - 1] + steps[n / 2]);
  return {kept.size(), static_cast<double>(widths.size()) / static_cast<double>(kept.size()),
          mean,        std::sqrt(var) / mean,
          median,      warnings};
}

std::string drive_row(const std::string& replay, const std::string& video, const std::string& mount, double from_s,
                      int width = 14) {
  const DriveMeasures m = drive_measures(replay, from_s);
  if (m.frames == 0) return "";
  char row[200];
  std::snprintf(row, sizeof row, "%-28s %-*s %6zu %5.0f%% %8.3f %5.1f%% %8.1f %8d", video.c_str(), width, mount.c_str(),
                m.frames, 100.0 * m.ok, m.width_mm / 1000.0, 100.0 * m.width_sd, m.step_mm, m.warnings);
  return row;
}

TEST(MeasureReal, EachDrivesRowIsItsReplaySummedUpFromTheFourthSecondWhenTheMountIsOff) {
  test::TempDir tmp;
  const std::string work = tmp.file("work"), drives = std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-drives";
  const test::ProcessResult r = test::run_process(
      {"python3", kMeasureReal, tmp.path(), "--drives", drives, "--ccdlane", CCDLANE_TOOL, "--keep", work});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  EXPECT_EQ(r.out.find("TuSimple"), std::string::npos) << "no stills in the data folder: no stills' table";
  for (const std::string video : {"project_video_segA.mp4", "project_video_segB.mp4"}) {
    for (const auto& [mount, dir, from_s] : {std::tuple{"nominal", "nominal", 0.0},
                                             {"pitch +5", "pitch_+5", 3.0},
                                             {"height x0.75", "height_x0.75", 3.0}}) {
      const std::string row = drive_row(work + "/drives/" + dir + "/" + video + ".jsonl", video, mount, from_s);
      EXPECT_NE(r.out.find(row + "\n"), std::string::npos) << row << "\nnot in\n" << r.out;
    }
    EXPECT_NE(r.out.find(video + std::string(28 - video.size(), ' ') + " pitch "), std::string::npos)
        << "each drive's mount calibrated: " << r.out;
  }
  // The targets: how many of the fourteen rows meet each (here: all four together, which
  // the printed counts must allow), and the calibrated pitches' agreement as printed.
  int all_met = 0;
  for (const std::string video : {"project_video_segA.mp4", "project_video_segB.mp4"})
    for (const char* dir : {"nominal", "pitch_+5", "pitch_-5", "yaw_+5", "yaw_-5", "height_x0.75", "height_x1.25"})
      all_met +=
          drive_measures(work + "/drives/" + dir + "/" + video + ".jsonl", std::string(dir) == "nominal" ? 0.0 : 3.0)
              .meets_targets();
  std::smatch counts;
  ASSERT_TRUE(std::regex_search(r.out, counts,
                                std::regex(R"(drives +14 rows, each target met in: ok (\d+), width sd (\d+), )"
                                           R"(offset step (\d+), warnings (\d+)\n)")))
      << r.out;
  int fewest = 14;
  for (int k = 1; k <= 4; ++k) fewest = std::min(fewest, std::stoi(counts[static_cast<std::size_t>(k)]));
  EXPECT_LE(all_met, fewest);
  EXPECT_EQ(test::count_of(r.out, std::string(31, ' ') + "project_video_seg"), 14 - all_met)
      << "each row missing a target named once: " << r.out;
  std::smatch pitches;
  ASSERT_TRUE(std::regex_search(
      r.out, pitches,
      std::regex(
          R"(mount calibration +pitches (-?[0-9.]+), (-?[0-9.]+) deg: ([0-9.]+) apart <= 0.3 deg: (met|NOT met)\n)")))
      << r.out;
  const double apart = std::abs(std::stod(pitches[1]) - std::stod(pitches[2]));
  EXPECT_NEAR(std::stod(pitches[3]), apart, 0.0015);
  EXPECT_EQ(pitches[4], apart <= 0.3 ? "met" : "NOT met");
}

// A drive recorded as a frame directory (`ccdlane record --out DIR`, as a user records
// their own car) is measured as a video is: its row is its replay's, and it is named by
// the directory. The video's first 50 frames, recorded.
// A drives folder in `drives` holding the camera file and segA's first 50 frames as
// `ccdlane record` writes them (segA_recorded/); false when recording failed.
bool record_segA_start(const std::string& drives) {
  const std::string source = std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-drives";
  std::filesystem::create_directories(drives);
  std::filesystem::copy_file(source + "/camera.toml", drives + "/camera.toml");
  const test::ProcessResult rec =
      test::run_process({CCDLANE_TOOL, "record", "video:" + source + "/project_video_segA.mp4", "--out",
                         drives + "/segA_recorded", "--count", "50"});
  EXPECT_EQ(rec.exit_status, 0) << rec.err;
  return rec.exit_status == 0;
}

TEST(MeasureReal, ADriveRecordedAsAFrameDirectoryIsMeasuredAsAVideoIs) {
  test::TempDir tmp;
  const std::string drives = tmp.file("drives"), work = tmp.file("work");
  ASSERT_TRUE(record_segA_start(drives));
  const test::ProcessResult r = test::run_process({"python3", kMeasureReal, tmp.path(), "--drives", drives, "--ccdlane",
                                                   CCDLANE_TOOL, "--keep", work, "--nominal-only"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  const std::string row = drive_row(work + "/drives/nominal/segA_recorded.jsonl", "segA_recorded", "nominal", 0.0);
  ASSERT_FALSE(row.empty()) << r.out;
  EXPECT_NE(r.out.find(row + "\n"), std::string::npos) << row << "\nnot in\n" << r.out;
  EXPECT_NE(row.find(" 50 "), std::string::npos) << "all 50 recorded frames measured: " << row;
}

// --nominal-only, a first look after a change: the stills' nominal row and each drive's
// nominal row, each what its kept replay scores, and nothing at another mount (no mount-off,
// calibrated or jittered rows, no mount calibration); the targets say only what was
// measured. With --more-mounts it is a usage error.
TEST(MeasureReal, NominalOnlyMeasuresTheNominalMountAlone) {
  test::TempDir tmp;
  const std::string data = tmp.file("data"), work = tmp.file("work"), drives = tmp.file("drives");
  std::filesystem::create_directories(data);
  ASSERT_TRUE(record_segA_start(drives));
  const std::string video = "segA_recorded";
  const test::ProcessResult r =
      test::run_process({"python3", kMeasureReal, data, "--tusimple", kStills, "--drives", drives, "--ccdlane",
                         CCDLANE_TOOL, "--keep", work, "--nominal-only"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  EXPECT_EQ(printed_row(r.out, "nominal"), scored_row(work + "/tusimple/nominal", "nominal")) << r.out;
  const std::string drive = drive_row(work + "/drives/nominal/" + video + ".jsonl", video, "nominal", 0.0);
  ASSERT_FALSE(drive.empty()) << r.out;
  EXPECT_NE(r.out.find(drive + "\n"), std::string::npos) << drive << "\nnot in\n" << r.out;
  for (const char* other : {"pitch ", "yaw ", "height ", "calibrated", "jittered", "Mount calibration",
                            "stills, mount off", "stills, nominal, jittered", "mount calibration"})
    EXPECT_EQ(r.out.find(other), std::string::npos) << other << " in\n" << r.out;
  EXPECT_EQ(
      std::distance(std::filesystem::directory_iterator(work + "/tusimple"), std::filesystem::directory_iterator{}), 1)
      << "only the nominal row's replay";
  EXPECT_NE(r.out.find("stills, nominal mount        ego found "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("drives                       1 rows, each target met in: "), std::string::npos) << r.out;

  const test::ProcessResult both = test::run_process({"python3", kMeasureReal, data, "--tusimple", kStills, "--ccdlane",
                                                      CCDLANE_TOOL, "--nominal-only", "--more-mounts"});
  EXPECT_EQ(both.exit_status, 2) << both.out << both.err;
  EXPECT_NE(both.err.find("--nominal-only measures the nominal mount alone"), std::string::npos) << both.err;
}

// A drive cut short (a recording whose copy ended mid-frame): replay processes its whole
// frames, says where it ends and fails; measure-real measures those frames, says why the
// drive ends there, and exits 1, as not everything was measured. Its first 2.3 s give no
// frames from the fourth second on, which the mount-off rows say instead of a 0 % row.
TEST(MeasureReal, ADriveCutShortIsMeasuredUpToWhereItEndsAndSaysWhy) {
  test::TempDir tmp;
  const std::string drives = tmp.file("drives"), work = tmp.file("work");
  const std::string source = std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-drives";
  std::filesystem::create_directories(drives);
  std::filesystem::copy_file(source + "/camera.toml", drives + "/camera.toml");
  {
    const std::string video = test::read_file(source + "/project_video_segA.mp4");
    std::ofstream(drives + "/segA_cut.mp4", std::ios::binary).write(video.data(), 3000000);
  }
  const test::ProcessResult r = test::run_process(
      {"python3", kMeasureReal, tmp.path(), "--drives", drives, "--ccdlane", CCDLANE_TOOL, "--keep", work});
  EXPECT_EQ(r.exit_status, 1) << r.out << r.err;
  const std::string replay = work + "/drives/nominal/segA_cut.mp4.jsonl";
  const std::size_t frames = test::json_lines(test::read_file(replay)).size();
  EXPECT_GT(frames, 25u) << "a second and more of whole frames before the cut";
  EXPECT_LT(frames, 75u) << "the cut is within the first 3 s";
  const std::string row = drive_row(replay, "segA_cut.mp4", "nominal", 0.0);
  ASSERT_FALSE(row.empty());
  EXPECT_NE(r.out.find(row + "\n"), std::string::npos) << row << "\nnot in\n" << r.out;
  EXPECT_NE(r.out.find("(the frames up to where it ends: ccdlane: " + drives + "/segA_cut.mp4: frame " +
                       std::to_string(frames) + ": cut short"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("segA_cut.mp4                 pitch +5            0   (none from second 4 on)"),
            std::string::npos)
      << r.out;
  std::size_t said = 0;
  for (std::size_t at = r.out.find("(the frames up to where it ends"); at != std::string::npos;
       at = r.out.find("(the frames up to where it ends", at + 1))
    ++said;
  EXPECT_EQ(said, 1u) << "the cut said once, not on every row of the drive: " << r.out;
}

// --conditions with drives: each drive's condition row is its replay with that condition
// at the nominal mount, every frame counted (the same replay `ccdlane replay --condition`
// gives, line for line). The first 50 frames of segA, recorded.
TEST(MeasureReal, EachDrivesConditionRowIsItsReplaySoAtTheNominalMount) {
  test::TempDir tmp;
  const std::string drives = tmp.file("drives"), work = tmp.file("work");
  ASSERT_TRUE(record_segA_start(drives));
  const test::ProcessResult r = test::run_process({"python3", kMeasureReal, tmp.path(), "--drives", drives, "--ccdlane",
                                                   CCDLANE_TOOL, "--keep", work, "--conditions", "--nominal-only"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  ASSERT_NE(r.out.find("Drives as other cameras and light give them"), std::string::npos) << r.out;
  for (const auto& [name, condition, dir] :
       {std::tuple{"blur 1.5 px", "blur=1.5", "condition_blur1.5"},
        std::tuple{"light x0.3 noise 3", "light=0.3,noise=3", "condition_light0.3_noise3"},
        std::tuple{"dapple x0.4", "dapple=0.4", "condition_dapple0.4"}}) {
    const std::string kept = work + "/drives/" + dir;
    EXPECT_EQ(test::read_file(kept + "/camera.toml"), test::read_file(work + "/drives/nominal/camera.toml")) << name;
    const test::ProcessResult again = test::run_process(
        {CCDLANE_TOOL, "replay", kept + "/camera.toml", drives + "/segA_recorded", "--condition", condition});
    ASSERT_EQ(again.exit_status, 0) << again.err;
    EXPECT_EQ(test::json_lines_without_latency(test::read_file(kept + "/segA_recorded.jsonl")),
              test::json_lines_without_latency(again.out))
        << name;
    const std::string row = drive_row(kept + "/segA_recorded.jsonl", "segA_recorded", name, 0.0, 20);
    EXPECT_NE(r.out.find(row + "\n"), std::string::npos) << row << "\nnot in\n" << r.out;
  }
}

}  // namespace
}  // namespace ccdlane
