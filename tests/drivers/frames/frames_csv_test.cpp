// frames.csv: columns in any order, gyro and truth columns, and every malformed row named
// by its line while the good rows are kept.
#include "drivers/frames/frames_csv.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(FramesCsv, ColumnsInAnyOrderWithGyroAndTruth) {
  const FramesCsv csv = parse_frames_csv(
      "# recorded on a test track\n"
      "truth_psi_deg, t_ns ,pitch_deg,file,source_name,roll_deg,truth_y0_0_mm,yaw_deg\r\n"
      "0.5,1000,2.0,a.pgm,x.jpg,-1.5,1750,90\r\n"
      "\n"
      "0.25,2000,,b.pgm,y.jpg,,,\r\n",
      "frames.csv");
  EXPECT_TRUE(csv.issues.empty()) << csv.issues.front();
  ASSERT_EQ(csv.rows.size(), 2u);
  EXPECT_EQ(csv.data_rows, 2u);
  EXPECT_TRUE(csv.has_gyro_columns);
  EXPECT_EQ(csv.rows[0].file, "a.pgm");
  EXPECT_EQ(csv.rows[0].t_ns, 1000);
  EXPECT_EQ(csv.rows[0].line, 3);
  ASSERT_TRUE(csv.rows[0].gyro);
  EXPECT_EQ(csv.rows[0].gyro->roll_deg, -1.5);
  EXPECT_EQ(csv.rows[0].gyro->pitch_deg, 2.0);
  EXPECT_EQ(csv.rows[0].gyro->yaw_deg, 90.0);
  EXPECT_FALSE(csv.rows[1].gyro);  // empty cells: no reading at that frame
  EXPECT_EQ(csv.rows[1].index, 1u);
  ASSERT_EQ(csv.truth_columns, (std::vector<std::string>{"truth_psi_deg", "truth_y0_0_mm"}));
  ASSERT_EQ(csv.truth.size(), 4u);
  EXPECT_EQ(csv.truth[0], 0.5);
  EXPECT_EQ(csv.truth[1], 1750.0);
  EXPECT_EQ(csv.truth[2], 0.25);
  EXPECT_TRUE(std::isnan(csv.truth[3]));
}

TEST(FramesCsv, OptionalVehicleColumns) {
  const FramesCsv csv = parse_frames_csv(
      "file,t_ns,turn_indicator,speed_kmh\n"
      "0.pgm,100,left,72.5\n"
      "1.pgm,200,,\n"
      "2.pgm,300,both,0\n"
      "3.pgm,400,hazard,70\n"  // line 5: an unknown indicator
      "4.pgm,500,right,-3\n",  // line 6: a negative speed
      "frames.csv");
  EXPECT_TRUE(csv.has_vehicle_columns);
  ASSERT_EQ(csv.rows.size(), 3u);
  EXPECT_EQ(csv.rows[0].speed_kmh, 72.5);
  EXPECT_EQ(csv.rows[0].indicator, TurnIndicator::left);
  EXPECT_FALSE(csv.rows[1].speed_kmh) << "an empty cell: no speed at that frame";
  EXPECT_EQ(csv.rows[1].indicator, TurnIndicator::none);
  EXPECT_EQ(csv.rows[2].speed_kmh, 0.0);
  EXPECT_EQ(csv.rows[2].indicator, TurnIndicator::both);
  ASSERT_EQ(csv.issues.size(), 2u);
  EXPECT_EQ(csv.issues[0], "frames.csv:5: turn_indicator: not none, left, right or both: \"hazard\"");
  EXPECT_EQ(csv.issues[1], "frames.csv:6: speed_kmh: not a speed >= 0: \"-3\"");

  const FramesCsv plain = parse_frames_csv("file,t_ns\n0.pgm,100\n", "frames.csv");
  EXPECT_FALSE(plain.has_vehicle_columns);
  EXPECT_FALSE(plain.rows[0].speed_kmh);
  EXPECT_EQ(plain.rows[0].indicator, TurnIndicator::none);
}

TEST(FramesCsv, MalformedRowsAreNamedAndSkipped) {
  const FramesCsv csv = parse_frames_csv(
      "file,t_ns,roll_deg,pitch_deg,truth_phi_deg\n"  // line 1
      "0.pgm,100,0,0,0\n"                             // 2 good
      "1.pgm,abc,0,0,0\n"                             // 3 t_ns
      "2.pgm,100,0,0\n"                               // 4 field count
      ",200,0,0,0\n"                                  // 5 empty file
      "3.pgm,300,1,,0\n"                              // 6 half gyro
      "4.pgm,400,0,0,x\n"                             // 7 truth
      "5.pgm,50,0,0,0\n"                              // 8 backwards
      "6.pgm,500,nan,0,0\n"                           // 9 not finite
      "7.pgm,600,0,0,0\n",                            // 10 good
      "d/frames.csv");
  ASSERT_EQ(csv.rows.size(), 2u);
  EXPECT_EQ(csv.rows[1].file, "7.pgm");
  EXPECT_EQ(csv.rows[1].index, 8u);  // still the 0-based data row of the file
  EXPECT_EQ(csv.data_rows, 9u);
  EXPECT_EQ(csv.truth.size(), 2u);
  const std::vector<std::string> want = {
      "d/frames.csv:3: t_ns: not an integer: \"abc\"",
      "d/frames.csv:4: row has 4 fields, the header has 5",
      "d/frames.csv:5: file: empty",
      "d/frames.csv:6: pitch_deg: not a number: \"\"",
      "d/frames.csv:7: truth_phi_deg: not a number: \"x\"",
      "d/frames.csv:8: t_ns: 50 goes back in time (previous frame 100)",
      "d/frames.csv:9: roll_deg: not a number: \"nan\"",
  };
  EXPECT_EQ(csv.issues, want);
}

// Angles a 3DM-GX1 cannot report are damage, not priors: refused like any bad cell.
TEST(FramesCsv, GyroAnglesOutsideWhatTheGyroReportsAreRefused) {
  const FramesCsv csv = parse_frames_csv(
      "file,t_ns,roll_deg,pitch_deg,yaw_deg\n"
      "0.pgm,100,1e308,0,0\n"
      "1.pgm,200,0,90.5,0\n"
      "2.pgm,300,0,0,-181\n"
      "3.pgm,400,-180,-90,180\n",
      "d/frames.csv");
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_EQ(csv.rows[0].file, "3.pgm");
  const std::vector<std::string> want = {
      "d/frames.csv:2: roll_deg: outside -180..180 degrees",
      "d/frames.csv:3: pitch_deg: outside -90..90 degrees",
      "d/frames.csv:4: yaw_deg: outside -180..180 degrees",
  };
  EXPECT_EQ(csv.issues, want);
}

std::string header_error(const std::string& text) {
  try {
    parse_frames_csv(text, "f.csv");
  } catch (const FrameDirectoryError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FramesCsv, UnusableHeadersAreErrors) {
  EXPECT_EQ(header_error(""), "f.csv: empty (no header line)");
  EXPECT_EQ(header_error("# only a comment\n"), "f.csv: empty (no header line)");
  EXPECT_EQ(header_error("file,time\n"), "f.csv:1: header needs the columns file and t_ns (no t_ns)");
  EXPECT_EQ(header_error("\nname,t_ns\n"), "f.csv:2: header needs the columns file and t_ns (no file)");
  EXPECT_EQ(header_error("file,t_ns,file\n"), "f.csv:1: column \"file\" appears twice");
  EXPECT_EQ(header_error("file,t_ns,roll_deg\n"), "f.csv:1: a gyro reading needs both roll_deg and pitch_deg columns");
}

TEST(FramesCsv, HeaderOnlyIsAnEmptyDirectory) {
  const FramesCsv csv = parse_frames_csv("file,t_ns\n", "f.csv");
  EXPECT_TRUE(csv.rows.empty());
  EXPECT_FALSE(csv.has_gyro_columns);
}

}  // namespace
}  // namespace ccdlane
