// TuSimple and CULane labels: points to 1-based pixels, TuSimple's angle-scaled threshold
// (a lane slanted at 45 degrees is hit up to 20 / cos 45 = 28.3 px at 1280 wide), the ego
// lanes, frames matched to labels by path, and malformed labels named by file and line.
#include "tools/ccdlane/tusimple_labels.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "app/config.hpp"
#include "tests/support/run_process.hpp"
#include "tools/ccdlane/command.hpp"
#include "tools/ccdlane/road_line_picture.hpp"

namespace ccdlane::cli {
namespace {

// Four lanes of a 1280x720 picture, as TuSimple writes them: a vertical one right of the
// centre, two slanted at 45 degrees (left of the centre, one nearer than the other) and
// one far right; -2 where a lane has no point.
const char* kLabel =
    R"({"raw_file": "clips/0313-1/6040/20.jpg", "image": "images/0000.jpg", "h_samples": [400, 500, 600, 700],)"
    R"( "lanes": [[700, 700, 700, 700], [500, 400, 300, 200], [600, 500, 400, 300], [-2, 1000, 1100, 1200]]})";

TEST(TuSimpleLabels, PointsThresholdsAndEgoLanes) {
  test::TempDir dir;
  const std::string path = dir.write("labels.jsonl", std::string(kLabel) + "\n\n");
  const std::vector<LabelledPicture> labels = read_tusimple_labels(path, 1280, 720);
  ASSERT_EQ(labels.size(), 1u);
  EXPECT_EQ(labels[0].images, (std::vector<std::string>{"images/0000.jpg", "clips/0313-1/6040/20.jpg"}));
  const std::vector<AnnotatedLane>& lanes = labels[0].lanes;
  ASSERT_EQ(lanes.size(), 4u);
  EXPECT_EQ(lanes[0].points.front(), Vec2(701, 401)) << "0-based labels become 1-based pixels";
  EXPECT_EQ(lanes[3].points.size(), 3u) << "-2 is no point";
  EXPECT_EQ(labels[0].rows, (std::vector<double>{401, 501, 601, 701})) << "the sampled rows, 1-based";
  EXPECT_DOUBLE_EQ(lanes[0].threshold_scale, 1.0);
  EXPECT_NEAR(lanes[1].threshold_scale, std::sqrt(2.0), 1e-12);
  // At the bottom row the lanes stand at 701, 101, 201 and 1301: the own lane's are the
  // nearest either side of the centre (640.5).
  EXPECT_TRUE(lanes[0].ego);
  EXPECT_FALSE(lanes[1].ego);
  EXPECT_TRUE(lanes[2].ego);
  EXPECT_FALSE(lanes[3].ego);
}

TEST(TuSimpleLabels, ScoredWithTheAngleScaledThreshold) {
  // A slanted lane (a road line 1.8 m right of the camera) labelled dx pixels beside where
  // the reported line is: dx between the plain threshold and the angle-scaled one is a
  // miss by the plain rule and a hit by TuSimple's.
  const Config c = default_config();
  const CameraModel cam(c.camera, c.nominal_pose());
  const RoadLine line{-1800.0, 0.0, 0.0};
  AnnotatedLane lane;
  for (int row = 330; row <= 600; row += 10)
    if (const auto x = road_line_column_at_row(cam, line, row, 500, 300000)) lane.points.emplace_back(*x, row);
  ASSERT_GT(lane.points.size(), 20u);
  const double scale = tusimple_threshold_scale(lane);
  ASSERT_GT(scale, 1.2) << "the lane is slanted";
  const double threshold = ScoreRules::threshold_for_width(ScoreRules{}.threshold_px, c.camera.Nu);
  const double dx = threshold * (1.0 + scale) / 2.0;
  for (Vec2& p : lane.points) p.x() += dx;
  const std::vector<RoadLine> reported{line};
  lane.threshold_scale = 1.0;
  EXPECT_EQ(score_frame({&lane, 1}, c.camera.Nu, cam, reported).found, 0);
  lane.threshold_scale = scale;
  const FrameScore s = score_frame({&lane, 1}, c.camera.Nu, cam, reported);
  EXPECT_EQ(s.found, 1);
  EXPECT_EQ(s.hit_points, lane.points.size());
  EXPECT_EQ(s.false_lines, 0);
}

TEST(TuSimpleLabels, FramesAreMatchedByTheEndOfTheirPath) {
  EXPECT_TRUE(same_picture("/data/tusimple/images/0000.jpg", "images/0000.jpg"));
  EXPECT_TRUE(same_picture("clips/0313-1/6040/20.jpg", "clips/0313-1/6040/20.jpg"));
  EXPECT_TRUE(same_picture("/x/clips/0313-1/6040/20.jpg", "clips/0313-1/6040/20.jpg"));
  EXPECT_FALSE(same_picture("/x/clips/0313-1/6041/20.jpg", "clips/0313-1/6040/20.jpg"));
  EXPECT_FALSE(same_picture("/data/myimages/0000.jpg", "images/0000.jpg")) << "only at a path separator";
  EXPECT_FALSE(same_picture("", "images/0000.jpg"));
}

TEST(TuSimpleLabels, CulaneLinesAreXYPairs) {
  test::TempDir dir;
  const std::string path = dir.write("00000.lines.txt", "100.5 700 200 600 300 500 \n900 700 850 600\n");
  const std::vector<AnnotatedLane> lanes = read_culane_lines(path, 1640, 590);
  ASSERT_EQ(lanes.size(), 2u);
  EXPECT_EQ(lanes[0].points.size(), 3u);
  EXPECT_EQ(lanes[0].points[0], Vec2(101.5, 701));
  EXPECT_EQ(lanes[1].points[1], Vec2(851, 601));
  const std::string odd = dir.write("odd.lines.txt", "1 2 3\n");
  EXPECT_THROW(read_culane_lines(odd, 1640, 590), UsageError);
}

TEST(TuSimpleLabels, MalformedLabelsAreNamedByFileAndLine) {
  test::TempDir dir;
  auto message = [&](const std::string& text) {
    const std::string path = dir.write("bad.jsonl", std::string(kLabel) + "\n" + text + "\n");
    try {
      read_tusimple_labels(path, 1280, 720);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("[1, 2]").find("bad.jsonl:2: not a JSON object"), std::string::npos);
  EXPECT_NE(message(R"({"h_samples": [1], "lanes": [[1]]})").find("bad.jsonl:2: no \"raw_file\" or \"image\""),
            std::string::npos);
  EXPECT_NE(message(R"({"image": "a", "h_samples": [1, 2], "lanes": [[1]]})").find("one x per h_sample (2)"),
            std::string::npos);
  EXPECT_NE(message(R"({"image": "a", "h_samples": [1], "lanes": [["x"]]})").find("hold numbers"), std::string::npos);
}

}  // namespace
}  // namespace ccdlane::cli
