// Floors on the real data in tests/data (the two Udacity drives as MP4 through the
// project's video reader, the ten TuSimple stills with their labels), run through the
// `ccdlane` tool as a user runs it. A floor is what the code reached when it was set,
// less a margin from the data's own spread: for a share of n frames, three binomial
// standard deviations, sqrt(p (1 - p) / n); for a count of lines, two Poisson ones,
// sqrt(count); for a spread, three standard errors of an sd, sd / sqrt(2 n). They guard
// against losing what works; the targets of docs/real-roads.md are far above them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/median.hpp"
#include "tests/support/json_lines.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Json = nlohmann::json;
const std::string kTool = CCDLANE_TOOL;
const std::string kData = std::string(CCDLANE_TEST_DATA_DIR) + "/real";

using test::json_lines;

// The share of a drive's frames that are ok, the lane width's spread relative to its
// mean, and the warnings fired; the lane filter's lateral velocity (its median over the
// frames, and the median of its sigma) and the drift the solved offsets themselves show
// from the first ok frame to the last (their change over the time between).
struct DriveFigures {
  int frames = 0, ok = 0, warnings = 0;
  double width_sd = 0.0, mean_width_mm = 0.0;
  double lateral_velocity_mps = 0.0, sigma_lateral_velocity_mps = 0.0, offset_drift_mps = 0.0;
};

// `input`: a video or a frame directory; `condition`, if any, replay's --condition.
DriveFigures replay_drive(const std::string& input, const std::string& condition = "",
                          const std::string& camera = kData + "/udacity-drives/camera.toml",
                          std::vector<double>* heights = nullptr) {
  std::vector<std::string> command = {kTool, "replay", camera, input};
  if (!condition.empty()) command.insert(command.end(), {"--condition", condition});
  const auto r = test::run_process(command);
  EXPECT_EQ(r.exit_status, 0) << r.err;
  DriveFigures f;
  double sum = 0, sum2 = 0;
  std::vector<double> velocity, sigma;
  double first_offset = 0, first_t = 0, last_offset = 0, last_t = 0;
  for (const Json& e : json_lines(r.out)) {
    ++f.frames;
    f.warnings += e["ldw"]["fired"] != "none";
    if (!e["ldw"]["lateral_velocity_mps"].is_null()) {
      velocity.push_back(e["ldw"]["lateral_velocity_mps"].get<double>());
      sigma.push_back(e["ldw"]["sigma"]["lateral_velocity_mps"].get<double>());
    }
    if (!e["ok"].get<bool>()) continue;
    const double offset = e["lateral_offset_mm"].get<double>() * 1e-3, t = e["t_ns"].get<double>() * 1e-9;
    if (f.ok++ == 0) first_offset = offset, first_t = t;
    last_offset = offset, last_t = t;
    const double w = e["lane_width_mm"].get<double>();
    sum += w, sum2 += w * w;
    if (heights) heights->push_back(e["H_mm"].get<double>());
  }
  f.mean_width_mm = f.ok ? sum / f.ok : 0.0;
  f.lateral_velocity_mps = median_in_place(velocity);
  f.sigma_lateral_velocity_mps = median_in_place(sigma);
  f.offset_drift_mps = last_t > first_t ? (last_offset - first_offset) / (last_t - first_t) : 0.0;
  const double mean = f.ok ? sum / f.ok : 0.0;
  f.width_sd = f.ok > 1 ? std::sqrt(std::max(0.0, sum2 / f.ok - mean * mean)) / mean : 0.0;
  return f;
}

// With every frame ok the binomial sd is 0: the margin is then one frame's share of it,
// as if one of the n had failed.
double share_floor(double reached, int n) {
  const double p = std::min(reached, 1.0 - 1.0 / n);
  return reached - 3.0 * std::sqrt(p * (1.0 - p) / n);
}

// A drive's figures when its floors were set: frames, the share ok, the width's sd.
struct DriveReached {
  const char* file;
  int frames;
  double ok_reached, width_sd_reached;
};

// Its replay against them: the share ok and the width's sd within their spread, every
// frame replayed, and no warning (the car keeps its lane: a warning is never right).
void expect_drive_floors(const DriveFigures& f, const DriveReached& c) {
  EXPECT_EQ(f.frames, c.frames) << c.file;
  EXPECT_GE(static_cast<double>(f.ok) / f.frames, share_floor(c.ok_reached, c.frames)) << c.file;
  EXPECT_LE(f.width_sd, c.width_sd_reached * (1.0 + 3.0 / std::sqrt(2.0 * f.ok))) << c.file;
  EXPECT_EQ(f.warnings, 0) << c.file << ": the car keeps its lane: a warning is never right";
}

TEST(RealRoads, UdacityDrivesFromTheirVideos) {
  // Reached when the floors were set (nominal camera.toml, mount unknown; the search's
  // pose from the lines of bars and heights a step either side; yellow bars kept despite
  // their colour bled beside them; lines along the road's direction, scatter up to 1.1
  // px; one paint width for most of a line's marks, a worn dash allowed; the lane-width
  // prior on the own lane's lines; a line's consensus weighted by its marks' contrast):
  // segA 210 of 211 ok, width sd 1.55 % of its mean (1.91 % before the weighting); segB
  // 185 of 186, 2.05 % (2.09 %).
  for (const DriveReached& c : {DriveReached{"project_video_segA.mp4", 211, 210.0 / 211, 0.0155},
                                DriveReached{"project_video_segB.mp4", 186, 185.0 / 186, 0.0205}}) {
    const DriveFigures f = replay_drive(kData + "/udacity-drives/" + c.file);
    expect_drive_floors(f, c);
    // The camera is yawed 1.4 degrees on the car (calibrate mount), which the configured
    // mount (0) does not know: read as a heading, that was 0.44-0.48 m/s of drift the
    // offsets never showed. The lane filter's lateral velocity is the offsets' own drift,
    // within three of its sigmas (it reached 0.018 and 0.003 m/s from it, sigma 0.04).
    EXPECT_NEAR(f.lateral_velocity_mps, f.offset_drift_mps, 3.0 * f.sigma_lateral_velocity_mps) << c.file;
  }
}

// A softer camera: the drives with a Gaussian blur of 1.5 px. Its edges' ramps reached
// the step test's window and flagged the dashes' bars: segA was ok on 110 of 211 frames,
// segB on 119 of 186. The row filter measures the blur from its bars' edges and reads
// the test past the ramp (MarkScanner::step_window_offset): 207 and 179 when the floors
// were set, width sd 1.6 and 2.0 % of the mean, no warning.
TEST(RealRoads, UdacityDrivesBlurredAsASofterCameraWouldGiveThem) {
  for (const DriveReached& c : {DriveReached{"project_video_segA.mp4", 211, 207.0 / 211, 0.0160},
                                DriveReached{"project_video_segB.mp4", 186, 179.0 / 186, 0.0200}})
    expect_drive_floors(replay_drive(kData + "/udacity-drives/" + c.file, "blur=1.5"), c);
}

// A noisier camera: segB (pale concrete, where its paint's contrast is low) with pixel
// noise of sigma 6. The noise's bars inside the lane were clutter and refused the tracked
// lane on 17 frames (166 of 186 ok); inside a lane whose lines continue a tracked lane's,
// bars fainter than a quarter of its lines' are the picture's noise
// (kTrackedFaintClutterShare): 184 when the floor was set, width sd 2.0 %, no warning.
TEST(RealRoads, SegBThroughPixelNoiseAsANoisierCameraWouldGiveIt) {
  expect_drive_floors(replay_drive(kData + "/udacity-drives/project_video_segB.mp4", "noise=6"),
                      DriveReached{"project_video_segB.mp4", 186, 184.0 / 186, 0.0200});
}

// A height the user measured stands against a lane-width prior for other roads. segA's
// camera at the height `calibrate mount` finds for it (1.20 m; lanes 3.66 m wide), given
// as known ([prior] H_mm = [1200, 30]), with a prior of 4.5 m lanes: the first second's
// lanes, 3.7 m wide, once took the height to 1.47 m, where every frame then disagreed
// with the height prior (25 of 211 ok). The height is the user's; the lanes measure
// 3.66 m within what the height's 30 mm makes of them.
TEST(RealRoads, AMeasuredHeightStandsAgainstALaneWidthPriorOfOtherRoads) {
  std::ifstream in(kData + "/udacity-drives/camera.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string camera = text.str();
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"H_mm = 1300.0", "H_mm = 1200.0"},
        {"lane_width_mm = [3660.0, 300.0]", "lane_width_mm = [4500.0, 300.0]\nH_mm = [1200.0, 30.0]"}}) {
    const auto at = camera.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    camera.replace(at, from.size(), to);
  }
  test::TempDir dir;
  std::vector<double> heights;
  const DriveFigures f =
      replay_drive(kData + "/udacity-drives/project_video_segA.mp4", "", dir.write("camera.toml", camera), &heights);
  expect_drive_floors(f, {"project_video_segA.mp4", 211, 211.0 / 211, 0.0162});
  for (const double h : heights) EXPECT_EQ(h, 1200.0);
  EXPECT_NEAR(f.mean_width_mm, 3660.0, 2.0 * 3660.0 * 30.0 / 1200.0);
}

// A camera at 5 frames/s, or a daemon that drops four frames in five under load: the
// drives' every fifth frame (decoded by `ccdlane record`, 200 ms apart), tracked as at
// 25 frames/s, the lines' gates set for 40 ms (docs/real-roads.md "Lower frame rates").
TEST(RealRoads, UdacityDrivesAtAFifthOfTheirFrameRate) {
  struct Case {
    const char* file;
    int frames;
    double width_sd_reached;
  };
  // Reached when the floors were set: every frame ok, width sd 1.52 % (segA) and 1.95 %
  // (segB) of the mean.
  for (const Case& c : {Case{"project_video_segA.mp4", 43, 0.0152}, Case{"project_video_segB.mp4", 38, 0.0195}}) {
    test::TempDir decoded, fifth;
    const auto record = test::run_process({kTool, "record", "video:" + kData + "/udacity-drives/" + c.file, "--config",
                                           kData + "/udacity-drives/camera.toml", "--out", decoded.file("frames")});
    ASSERT_EQ(record.exit_status, 0) << record.err;
    std::istringstream csv(test::read_file(decoded.file("frames/frames.csv")));
    std::string line, kept = "file,t_ns\n";
    std::getline(csv, line);  // the header
    for (int row = 0; std::getline(csv, line); ++row)
      if (row % 5 == 0) kept += decoded.file("frames/") + line + "\n";
    fifth.write("frames.csv", kept);
    const DriveFigures f = replay_drive(fifth.path());
    EXPECT_EQ(f.frames, c.frames) << c.file;
    EXPECT_GE(static_cast<double>(f.ok) / f.frames, share_floor(1.0, c.frames)) << c.file;
    EXPECT_LE(f.width_sd, c.width_sd_reached * (1.0 + 3.0 / std::sqrt(2.0 * f.ok))) << c.file;
    EXPECT_EQ(f.warnings, 0) << c.file << ": the car keeps its lane: a warning is never right";
  }
}

// `calibrate mount` on a drive: its pitch and sigma from the printed summary.
struct Pitch {
  double deg = 0.0, sigma_deg = 0.0;
};

Pitch calibrated_pitch(const std::string& video) {
  const auto r = test::run_process({kTool, "calibrate", "mount", kData + "/udacity-drives/camera.toml", video});
  EXPECT_EQ(r.exit_status, 0) << r.err;
  Pitch p;
  const auto at = r.err.find("theta = ");
  EXPECT_NE(at, std::string::npos) << r.err;
  if (at != std::string::npos) std::sscanf(r.err.c_str() + at, "theta = %lf +/- %lf", &p.deg, &p.sigma_deg);
  return p;
}

TEST(RealRoads, TheMountCalibratedOnEitherDriveOfOneCarHasOnePitch) {
  // segA (asphalt, a bend of about 1 km, dashes) and segB (a concrete bridge) come from the
  // same car and camera: their pitches agree within the 0.3 degrees (-1.706 and
  // -1.561 at 2026-12-07). Each sigma is its own drive's spread about its mean, which
  // leaves out how the two roads' vertical profiles differ: solved on quarters of each
  // drive (2 s each) the pitch moves by 0.09 degrees on segA and 0.26 on segB, and a
  // refit with the road's vertical curve finds crests of 2-4 km on the bridge
  // (docs/real-roads.md). Three sigmas of the difference (0.144-0.147 degrees) was this
  // test's bound until then, met and missed by the last digit of the pitches.
  const Pitch a = calibrated_pitch(kData + "/udacity-drives/project_video_segA.mp4");
  const Pitch b = calibrated_pitch(kData + "/udacity-drives/project_video_segB.mp4");
  EXPECT_GT(a.sigma_deg, 0.0);
  EXPECT_GT(b.sigma_deg, 0.0);
  EXPECT_NEAR(a.deg, b.deg, 0.3) << "apart by " << std::abs(a.deg - b.deg) / std::hypot(a.sigma_deg, b.sigma_deg)
                                 << " sigmas of their difference";
}

// A still whose picture cannot be read (cut short) is alone too: it says so (no_frame),
// and carries nothing of the still before it: no coasting line, no tracking state.
TEST(RealRoads, AnUnreadableStillCarriesNothingOfTheStillBefore) {
  test::TempDir dir, out;
  const std::string picture = test::read_file(kData + "/tusimple/images/0001.jpg");
  dir.write("cut.jpg", picture.substr(0, picture.size() / 3));
  dir.write("frames.csv",
            "file,t_ns\n" + kData + "/tusimple/images/0000.jpg,0\n" + dir.file("cut.jpg") + ",1000000000\n");
  const auto replay = test::run_process(
      {kTool, "replay", kData + "/tusimple/camera.toml", dir.path(), "--stills", "--out", out.file("r.jsonl")});
  ASSERT_EQ(replay.exit_status, 0) << replay.err;
  EXPECT_NE(replay.err.find(dir.file("cut.jpg") + ": truncated"), std::string::npos) << replay.err;
  const std::vector<Json> e = json_lines(test::run_process({"/bin/cat", out.file("r.jsonl")}).out);
  ASSERT_EQ(e.size(), 2u);
  ASSERT_TRUE(e[0]["ok"].get<bool>()) << "the still before has a lane to carry";
  EXPECT_EQ(e[1]["reason"], "no_frame");
  EXPECT_EQ(e[1]["state"], "searching");
  EXPECT_TRUE(e[1]["lines"].empty()) << e[1]["lines"];
}

TEST(RealRoads, TuSimpleStillsEachAlone) {
  // The stills as frames of one directory, named by absolute path, each replayed alone.
  test::TempDir dir, out;  // the output may not lie inside the input
  std::string csv = "file,t_ns\n";
  for (int i = 0; i < 10; ++i)
    csv += kData + "/tusimple/images/000" + std::to_string(i) + ".jpg," + std::to_string(i) + "000000000\n";
  dir.write("frames.csv", csv);
  const std::string camera = kData + "/tusimple/camera.toml";
  const auto replay =
      test::run_process({kTool, "replay", camera, dir.path(), "--stills", "--out", out.file("r.jsonl")});
  ASSERT_EQ(replay.exit_status, 0) << replay.err;
  const std::vector<Json> estimates = json_lines(test::run_process({"/bin/cat", out.file("r.jsonl")}).out);
  for (const Json& e : estimates) EXPECT_EQ(e["state"], "searching") << "a still has no previous frame";
  // The stills' folder as published, without frames.csv: the same stills, in name order.
  const std::string images = kData + "/tusimple/images";
  const auto folder = test::run_process({kTool, "replay", camera, images, "--stills", "--out", out.file("f.jsonl")});
  ASSERT_EQ(folder.exit_status, 0) << folder.err;
  EXPECT_NE(folder.err.find(images + ": no frames.csv: its 10 pictures in name order, 40 ms apart"), std::string::npos)
      << folder.err;
  const std::vector<Json> from_folder = json_lines(test::run_process({"/bin/cat", out.file("f.jsonl")}).out);
  ASSERT_EQ(from_folder.size(), estimates.size());
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    EXPECT_EQ(from_folder[i]["frame"], estimates[i]["frame"]);
    EXPECT_EQ(from_folder[i]["ok"], estimates[i]["ok"]) << i;
    EXPECT_EQ(from_folder[i]["lines"], estimates[i]["lines"]) << i;
  }
  const auto score = test::run_process(
      {kTool, "score", camera, dir.path(), out.file("r.jsonl"), kData + "/tusimple/labels.jsonl", "--json"});
  ASSERT_EQ(score.exit_status, 0) << score.err;
  const Json t = Json::parse(score.out)["total"];
  EXPECT_EQ(t["frames"], 10);
  EXPECT_EQ(t["ego_lanes"], 20) << "two own-lane lines labelled in each still";
  // Reached when the floor was set (the search's pose from the lines of bars, heights a
  // step either side of the configured one; lines beyond the own lane reported only with
  // a line's support or as a dash beside a lane; markers in sunlight as a cap beside its
  // shadow; a few markers beside a joint between slabs as a line along the joint, at
  // its markers; a row of dots beside the only full line, a single line solved at its
  // search pose's pitch; the own lane's other line looked for in the picture; a line's
  // consensus weighted by contrast): 19 of the 20 own-lane lines found (15 when this
  // floor was first set; 13 before the rows of dots, 11 before the joints, 10 before the
  // shadowed markers), 1 false line of the 28 reported (0 before the rows of dots, 1
  // before the joints; 3 of 17 before lines beyond the own lane needed support): Poisson
  // margins, at least one line's for the false ones.
  EXPECT_GE(t["ego_found"].get<double>(), 19.0 - 2.0 * std::sqrt(19.0));
  EXPECT_LE(t["false_lines"].get<double>(), 1.0 + 2.0 * std::sqrt(1.0));
}

// The TuSimple camera.toml with its mount's pitch and height changed as a user's error.
std::string tusimple_camera_off(double pitch_deg, double height_factor) {
  std::ifstream in(kData + "/tusimple/camera.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const auto replace = [&s](const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
  };
  replace("theta_deg = 0.0", "theta_deg = " + std::to_string(pitch_deg));
  replace("H_mm = 1300.0", "H_mm = " + std::to_string(1300.0 * height_factor));
  return s;
}

// One still replayed alone (replay --stills, with `options` added) with `camera`, and
// `ccdlane score`'s total for it against its labels, with the replay's estimate.
struct ScoredStill {
  Json total, estimate;
};
ScoredStill score_still(const std::string& still, const std::string& camera,
                        const std::vector<std::string>& options = {}) {
  test::TempDir dir, out;
  dir.write("frames.csv", "file,t_ns\n" + kData + "/tusimple/images/" + still + ".jpg,0\n");
  std::vector<std::string> command = {kTool, "replay", camera, dir.path(), "--stills", "--out", out.file("r.jsonl")};
  command.insert(command.end(), options.begin(), options.end());
  const auto replay = test::run_process(command);
  EXPECT_EQ(replay.exit_status, 0) << replay.err;
  const auto score = test::run_process(
      {kTool, "score", camera, dir.path(), out.file("r.jsonl"), kData + "/tusimple/labels.jsonl", "--json"});
  EXPECT_EQ(score.exit_status, 0) << score.err;
  if (replay.exit_status != 0 || score.exit_status != 0) return {};
  return {Json::parse(score.out)["total"], json_lines(test::read_file(out.file("r.jsonl"))).at(0)};
}

TEST(RealRoads, AStillsOwnLaneDoesNotDependOnHowFarOffTheMountIs) {
  // Still 0004: four lines labelled, the own lane's and one beyond each. The search
  // tries poses in an order (the picture's vanishing point, the mount, pitched steps)
  // and the detection from each groups other bars. When it took the first pose that
  // made a lane, a mount 10-15 % off in height found only one of the own lane's lines.
  // Of the poses at the height of the first lane it takes the one whose own lane holds
  // the most picks: both, from each of these mounts.
  struct Off {
    double pitch_deg, height_factor;
  };
  for (const Off off :
       {Off{0.0, 1.0}, Off{1.0, 1.0}, Off{-1.0, 1.0}, Off{2.5, 1.0}, Off{0.0, 0.85}, Off{0.0, 0.9}, Off{0.0, 1.15}}) {
    test::TempDir dir;
    const std::string camera = dir.write("camera.toml", tusimple_camera_off(off.pitch_deg, off.height_factor));
    EXPECT_EQ(score_still("0004", camera).total["ego_found"], 2)
        << "pitch " << off.pitch_deg << " deg, height x" << off.height_factor;
  }
}

// Still 0007's right line is a faint row of raised markers. The search finds its lane
// only from its highest height step (1.69 times the configured 1.3 m), where the lane is
// 1.38 lanes wide: the height its width says, 1.6 m, is one the search tries, and the
// look from there finds both own lines. While a first solve's height was taken only
// within a configured height's error of its own pose's (a third), it was not (1 of 2).
TEST(RealRoads, AStillsHeightIsTakenFromItsLanesWidthAtAnyHeightTheSearchTries) {
  const ScoredStill s = score_still("0007", kData + "/tusimple/camera.toml");
  ASSERT_FALSE(s.total.is_null());
  EXPECT_EQ(s.total["ego_found"], 2);
  EXPECT_EQ(s.total["false_lines"], 0);
  EXPECT_NEAR(s.estimate["H_mm"].get<double>(), 1600.0, 0.1 * 1600.0) << "the height its lane's width says";
}

// A search's look again plans its rows and casts the lines beyond the own lane from its
// first solve's pose, which the lines it finds then move. Still 0000 as a 640x360 camera
// and still 0007 as a 1920x1080 one (replay --condition scale) solve a degree or more
// away from the pose they looked from, and the next lane's line beyond one own line,
// labelled, was not found from there (2 of the 4 labelled lines each). Looked for once
// more from the lane's solve, it is: 3 of 4 each when this was written, and no false
// line. Not at the recorded size, where no still of 0000-0009 moves that far.
TEST(RealRoads, AStillsNextLanesLinesAreLookedForFromThePoseItsLaneWasSolvedTo) {
  for (const auto& [still, scale] : {std::pair{"0000", "0.5"}, std::pair{"0007", "1.5"}}) {
    const Json t =
        score_still(still, kData + "/tusimple/camera.toml", {"--condition", std::string("scale=") + scale}).total;
    ASSERT_FALSE(t.is_null()) << still;
    EXPECT_EQ(t["lanes"], 4) << still;
    EXPECT_EQ(t["ego_found"], 2) << still;
    EXPECT_EQ(t["found"], 3) << still << " at x" << scale;
    EXPECT_EQ(t["false_lines"], 0) << still << " at x" << scale;
  }
}

// A car standing in traffic sees one picture frame after frame: the first a search, the
// others tracked from the pose and lines the frame before solved. Still 0002 from a
// mount 15 % too high: the search finds the lane, the first second's widths settle the
// height and rescale the lines, and the tracked look from there found no lane, nor the
// look afresh from the same pose; a second of frames went without one until the next
// search. The pose the search found the lane from, looked from once more, keeps it:
// every frame ok (35 of 60 before).
TEST(RealRoads, AHeldStillKeepsItsLane) {
  test::TempDir dir, out;
  std::string csv = "file,t_ns\n";
  for (long long k = 0; k < 60; ++k) csv += kData + "/tusimple/images/0002.jpg," + std::to_string(k * 40000000) + "\n";
  dir.write("frames.csv", csv);
  const std::string camera = out.write("camera.toml", tusimple_camera_off(0.0, 1.15));
  const auto replay = test::run_process({kTool, "replay", camera, dir.path(), "--out", out.file("r.jsonl")});
  ASSERT_EQ(replay.exit_status, 0) << replay.err;
  int ok = 0, frames = 0;
  for (const Json& e : json_lines(test::run_process({"/bin/cat", out.file("r.jsonl")}).out)) {
    ok += e["ok"].get<bool>();
    ++frames;
  }
  EXPECT_EQ(frames, 60);
  // All 60 when the floor was set; the margin as for a drive whose frames are all ok.
  EXPECT_GE(ok, 59);
}

// Still 0000 held at the nominal mount: a tracked frame's solve gave a pose from which its
// own lane was not found again, nor from the search's pose; 15 frames in a row went
// without a lane (44 of 60 ok). Looked at once more from the pose the last frame's lane
// was found from, it loses it for a frame at a time (55 of 60 when this was written).
TEST(RealRoads, AHeldStillIsLookedAtFromThePoseItsLastLaneWasFoundFrom) {
  test::TempDir dir, out;
  std::string csv = "file,t_ns\n";
  for (long long k = 0; k < 60; ++k) csv += kData + "/tusimple/images/0000.jpg," + std::to_string(k * 40000000) + "\n";
  dir.write("frames.csv", csv);
  const auto replay =
      test::run_process({kTool, "replay", kData + "/tusimple/camera.toml", dir.path(), "--out", out.file("r.jsonl")});
  ASSERT_EQ(replay.exit_status, 0) << replay.err;
  int ok = 0, run = 0, longest_run = 0;
  for (const Json& e : json_lines(test::run_process({"/bin/cat", out.file("r.jsonl")}).out)) {
    const bool lane = e["ok"].get<bool>();
    ok += lane;
    run = lane ? 0 : run + 1;
    longest_run = std::max(longest_run, run);
  }
  EXPECT_GE(ok, 53) << "55 when written, less two frames";
  EXPECT_LE(longest_run, 2) << "a frame or two at a time, never a second";
}

}  // namespace
}  // namespace ccdlane
