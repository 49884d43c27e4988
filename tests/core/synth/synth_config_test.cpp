// The [synth] table of the configuration: defaults, every key, strict errors.
#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "tests/support/config_error.hpp"

namespace ccdlane {
namespace {

std::string error_of(const std::string& toml) { return test::config_error_of(toml, "s.toml"); }

TEST(SynthConfig, EmptyConfigGivesAThreeLaneHighway) {
  const Config c = parse_config("", "empty.toml");
  EXPECT_EQ(c.synth.lanes, 3);
  EXPECT_EQ(c.synth.ego_lane, 1);
  EXPECT_EQ(c.synth.lane_width_mm, 3600.0);
  EXPECT_EQ(c.synth.dashed, DashedLines::inner);
  EXPECT_EQ(c.synth.noise_sigma, 1.0);
  EXPECT_EQ(c.synth.bits, 8);
  EXPECT_TRUE(c.synth.gyro);
}

TEST(SynthConfig, ReadsEveryKey) {
  const Config c = parse_config(R"(
[synth]
seed = 7
frames = 12
rate_hz = 25
speed_mps = 20
lanes = 4
ego_lane = 2
lane_width_mm = 3500
line_width_mm = 100
edge_line_width_mm = 200
dashed = "all"
dash_length_mm = 6000
dash_gap_mm = 12000
curvature_per_mm = -2e-7
weave_mm = 100
weave_period_s = 5
pitch_bump_deg = 0.2
bump_period_s = 1
roll_sway_deg = 0.1
roll_period_s = 2
lane_change_at_s = 1.5
lane_change_s = 3
asphalt_grey = 80
texture_grey = 5
paint_grey = 220
sky_grey = 190
verge_grey = 60
gradient = 0.1
shadow_depth = 0.5
noise_sigma = 2
blur_px = 0.7
supersample = 2
bits = 12
gyro = false
gyro_noise_deg = 0.05
)",
                                "full.toml");
  const SynthConfig& s = c.synth;
  EXPECT_EQ(s.seed, 7u);
  EXPECT_EQ(s.frames, 12);
  EXPECT_EQ(s.lanes, 4);
  EXPECT_EQ(s.ego_lane, 2);
  EXPECT_EQ(s.dashed, DashedLines::all);
  EXPECT_EQ(s.curvature_per_mm, -2e-7);
  EXPECT_EQ(s.lane_change_at_s, 1.5);
  EXPECT_EQ(s.verge_grey, 60.0);
  EXPECT_EQ(s.blur_px, 0.7);
  EXPECT_EQ(s.supersample, 2);
  EXPECT_EQ(s.bits, 12);
  EXPECT_FALSE(s.gyro);
  EXPECT_EQ(s.gyro_noise_deg, 0.05);
}

TEST(SynthConfig, ReadsTheRealRoadKeysOffByDefault) {
  const SynthConfig off = parse_config("", "empty.toml").synth;
  EXPECT_FALSE(off.colour || off.yellow_left_edge || off.hard_shadows || off.barrier || off.night);
  EXPECT_EQ(off.surface, RoadSurface::asphalt);
  const SynthConfig s = parse_config(R"(
[synth]
colour = true
yellow_left_edge = true
yellow_paint_grey = 160
surface = "concrete"
concrete_grey = 180
hard_shadows = true
barrier = true
night = true
cars = 3
)",
                                     "colour.toml")
                            .synth;
  EXPECT_TRUE(s.colour && s.yellow_left_edge && s.hard_shadows && s.barrier && s.night);
  EXPECT_EQ(s.cars, 3);
  EXPECT_EQ(off.cars, 0);
  EXPECT_EQ(s.yellow_paint_grey, 160.0);
  EXPECT_EQ(s.surface, RoadSurface::concrete);
  EXPECT_EQ(s.concrete_grey, 180.0);
}

TEST(SynthConfig, StrictErrors) {
  EXPECT_EQ(error_of("[synth]\nlanes = 5\n"), "s.toml:2: synth.lanes: must be 2..4, got 5");
  EXPECT_EQ(error_of("[synth]\nego_lane = 3\n"), "s.toml:2: synth.ego_lane: must be a lane of the road, 0..2");
  EXPECT_EQ(error_of("[synth]\ndashed = \"some\"\n"),
            "s.toml:2: synth.dashed: must be \"inner\", \"all\" or \"none\", got \"some\"");
  EXPECT_EQ(error_of("[synth]\nnoise = 1\n"), "s.toml:2: synth.noise: unknown key");
  EXPECT_EQ(error_of("[synth]\nbits = 7\n"), "s.toml:2: synth.bits: must be 8 (mono8) or 9..16 (mono16)");
  EXPECT_EQ(error_of("[synth]\npaint_grey = 300\n"), "s.toml:2: synth.paint_grey: must be a grey level 0..255");
  EXPECT_EQ(error_of("[synth]\nbump_period_s = 0\n"), "s.toml:2: synth.bump_period_s: must be > 0");
  EXPECT_EQ(error_of("[synth]\ncurvature_per_mm = 1e-4\n"),
            "s.toml:2: synth.curvature_per_mm: must be within +-1e-5 (a radius of at least 50 m)");
  EXPECT_EQ(error_of("[synth]\nego_lane = 2\nlane_change_at_s = 3\n"),
            "s.toml:3: synth.lane_change_at_s: a lane change goes to the lane on the right, and ego_lane is the "
            "rightmost");
  EXPECT_EQ(error_of("[synth]\ngyro = 1\n"), "s.toml:2: synth.gyro: must be true or false, got an integer");
  EXPECT_EQ(error_of("[synth]\nsurface = \"gravel\"\n"),
            "s.toml:2: synth.surface: must be \"asphalt\" or \"concrete\", got \"gravel\"");
  EXPECT_EQ(error_of("[synth]\nconcrete_grey = 256\n"), "s.toml:2: synth.concrete_grey: must be a grey level 0..255");
  EXPECT_EQ(error_of("[synth]\ncars = 7\n"), "s.toml:2: synth.cars: must be 0..6");
  EXPECT_EQ(error_of("[synth]\ncolour = true\nbits = 12\n"),
            "s.toml:2: synth.colour: colour frames are rgb8: leave bits at 8");
}

}  // namespace
}  // namespace ccdlane
